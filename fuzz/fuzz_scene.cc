// libFuzzer target: the scene parser, and what a parsed scene reaches at once
// (the modal basis, the analysis basis, the orbits at one period). Any input
// must end in a scene or an InputError naming a field: never a crash, a hang
// (libFuzzer's -timeout) or memory exhaustion (-rss_limit_mb).
#include <cstddef>
#include <cstdint>
#include <string>

#include "nsmodal/atlas.h"
#include "nsmodal/error.h"
#include "nsmodal/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const nsmodal::Scene scene = nsmodal::ParseScene(text, "<fuzz>");
    const nsmodal::AnalysisBasis b(scene.model);
    nsmodal::SweepOptions opt;
    opt.threads = 1;
    for (int impacts : {1, 2}) nsmodal::OrbitsAt(b, 1.37 * b.Periods().minCoeff(), impacts, opt);
  } catch (const nsmodal::InputError&) {
  }
  return 0;
}
