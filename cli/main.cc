// nsmodal: nonsmooth modal analysis of vibro-impact oscillators.
#include "command_line.h"

int main(int argc, char** argv) { return nsmodal::cli::Main(argc, argv); }
