"""The command line of the mesh studies (bar_convergence.py, dropped_bar.py):
[OUT_DIR] [MAX_ELEMENTS], checked, the output folder made."""
import os
import sys


def out_and_max_elements(default_max):
    """(OUT_DIR, MAX_ELEMENTS) from sys.argv; exits naming a bad MAX_ELEMENTS."""
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("out", "examples")
    try:
        max_elements = int(sys.argv[2]) if len(sys.argv) > 2 else default_max
    except ValueError:
        sys.exit(f"MAX_ELEMENTS: must be an integer, got {sys.argv[2]!r}")
    if not 10 <= max_elements <= 2000:
        sys.exit(f"MAX_ELEMENTS: must be between 10 and 2000 (the meshes start at 10 elements), got {max_elements}")
    os.makedirs(out, exist_ok=True)
    return out, max_elements
