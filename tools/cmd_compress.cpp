// `adaptive-cpca compress`: transport file -> model.
#include <iostream>
#include <map>

#include "cluster/compress.h"
#include "dataset/file_info.h"
#include "model/model_file.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "tools/render_flags.h"

namespace acpca::cli {

namespace {

struct CompressArgs {
  CommonOptions common;
  CompressFlags compress;
  std::string input, out;
};

void run(const CompressArgs& a) {
  CompressOptions o = a.compress.options();
  refuseOutputsOverInputs({a.input}, {a.out, a.common.jsonPath});
  o.log = stderrLog("compress", a.common.quiet);
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  Model model = compressTransport(transport, o);
  writeModel(model, a.out);
  const long long peak = peakMemoryBytes();
  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << ": " << describeInWords(model) << ", peak memory "
              << formatBytes(peak) << "\n";
  nlohmann::json report = summaryJson(model);
  report.update(linearAlgebraJson());
  report.update({{"out", a.out},
                 {"rank_histogram", rankHistogramJson(model.ranks)},
                 {"peak_memory_bytes", peak}});
  writeJson(a.common.jsonPath, report);
}

}  // namespace

void registerCompress(CLI::App& app) {
  auto args = std::make_shared<CompressArgs>();
  auto* sub =
      app.add_subcommand("compress", "Compress a transport file into a clustered PCA model");
  sub->add_option("input", args->input, "Transport file (T_FILE)")->required();
  sub->add_option("--out", args->out, "Model file to write (HDF5)")->required();
  args->compress.add(*sub, false);
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
