// adaptive-cpca: the batch command line (docs: ../shared/docs/cli.md, README).
#include <sys/resource.h>

#include <iostream>

#include "precompute/transport/error.h"
#include "tools/commands.h"

namespace acpca::cli {
long long peakMemoryBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}
}  // namespace acpca::cli

int main(int argc, char** argv) {
  CLI::App app{"adaptive-cpca: relight fixed-view images under all-frequency environment lighting"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "adaptive-cpca 0.1.0");
  acpca::cli::registerPrecompute(app);
  acpca::cli::registerCompress(app);
  acpca::cli::registerRelight(app);
  acpca::cli::registerEnvmap(app);
  acpca::cli::registerInfo(app);
  acpca::cli::registerScenes(app);
  acpca::cli::registerBench(app);
  acpca::cli::registerEval(app);
  acpca::cli::registerAnalyze(app);
  acpca::cli::registerView(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const acpca::UserError& e) {
    std::cerr << "adaptive-cpca: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "adaptive-cpca: internal error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
