// `adaptive-cpca web`: a static site that relights a model on the GPU in a browser.
#include <iostream>

#include "core/error.h"
#include "lighting/environment.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "web/site_export.h"

namespace acpca::cli {

namespace {

struct WebArgs {
  CommonOptions common;
  std::string model, out, maxRank, title;
  std::vector<std::string> envs;
};

void run(const WebArgs& a) {
  WebExportOptions options;
  options.model = a.model;
  options.out = a.out;
  options.envs = a.envs;
  options.maxRank = RankLimit::parse(a.maxRank);
  options.title = a.title;
  refuseOutputsOverInputs(a.envs, {a.common.jsonPath});
  const WebExportReport report = exportWebPage(options);
  const double mb = 1e-6;
  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << "/index.html: " << report.files.size() << " files, "
              << report.pageBytes * mb << " MB (model " << report.modelBytes * mb << " MB, maps "
              << report.mapBytes * mb << " MB; " << report.seenTexels << " of "
              << report.latticeTexels << " directions seen)\n"
              << "serve it with: python3 -m http.server -d " << a.out << "\n";
  writeJson(a.common.jsonPath, {{"model", a.model},
                                {"out", a.out},
                                {"files", report.files},
                                {"page_bytes", report.pageBytes},
                                {"model_bytes", report.modelBytes},
                                {"map_bytes", report.mapBytes},
                                {"seen_texels", report.seenTexels},
                                {"lattice_texels", report.latticeTexels}});
}

}  // namespace

void registerWeb(CLI::App& app) {
  auto args = std::make_shared<WebArgs>();
  auto* sub = app.add_subcommand(
      "web", "Write a static web page that relights a model on the GPU in any browser");
  sub->add_option("model", args->model, "Model file (compress or build)")->required();
  sub->add_option("--out", args->out, "The site's directory (index.html and what it loads)")
      ->required();
  sub->add_option("--env", args->envs,
                  "Maps for the page's picker (repeatable; default sky): lat-long image files, "
                  "directories of them, " +
                      environmentGrammarList());
  sub->add_option("--max-rank", args->maxRank,
                  "Keep each cluster's first K bases, or a fraction or percentage of them");
  sub->add_option("--title", args->title, "The page's title (default: the model's file name)");
  args->common.add(*sub, false);
  nameParameters(*sub, {{"--max-rank", {"maximum rank"}}, {"--env", {"environment"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
