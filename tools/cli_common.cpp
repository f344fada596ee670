#include "tools/cli_common.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_guard.h"
#include "relight/environment.h"

namespace acpca::cli {

void CommonOptions::add(CLI::App& app, bool withThreads) {
  app.add_flag("-q,--quiet", quiet, "No progress output on stderr");
  app.add_option("--json", jsonPath, "Write machine-readable results to FILE (- for stdout)");
  if (withThreads)
    app.add_option("--threads", threads, "Worker threads (0: all cores)")
        ->check(CLI::NonNegativeNumber);
}

ThreadLimit::ThreadLimit(int threads)
    : threads_(threads > 0 ? threads : tbb::info::default_concurrency()) {
  control_ =
      std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads_);
}

ThreadLimit::~ThreadLimit() = default;

Progress::Progress(std::string label, std::string unit, bool quiet)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      quiet_(quiet),
      tty_(isatty(STDERR_FILENO)) {}

namespace {
std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  char buffer[32];
  if (s >= 3600)
    std::snprintf(buffer, sizeof buffer, "%ldh%02ldm", s / 3600, (s / 60) % 60);
  else if (s >= 60)
    std::snprintf(buffer, sizeof buffer, "%ldm%02lds", s / 60, s % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%lds", s);
  return buffer;
}
}  // namespace

void Progress::update(long long done, long long total) {
  if (quiet_) return;
  if (done < total && sinceLastPrint_.seconds() < (tty_ ? 0.25 : 5.0)) return;
  sinceLastPrint_.restart();
  const double elapsed = sinceStart_.seconds();
  const double rate = elapsed > 0 ? done / elapsed : 0;
  const double eta = rate > 0 ? (total - done) / rate : NAN;
  char line[256];
  std::snprintf(line, sizeof line, "%s: %lld/%lld %s (%.1f%%), %.3g %s/s, elapsed %s, ETA %s",
                label_.c_str(), done, total, unit_.c_str(), total ? 100.0 * done / total : 100.0,
                rate, unit_.c_str(), formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
  std::cerr << (tty_ ? "\r" : "") << line << (tty_ ? "\033[K" : "\n") << std::flush;
  printed_ = true;
}

void Progress::finish() {
  if (!quiet_ && printed_ && tty_) std::cerr << "\n";
}

void writeJson(const std::string& path, const nlohmann::json& value) {
  if (path.empty()) return;
  if (path == "-") {
    std::cout << value.dump(2) << std::endl;
    return;
  }
  writeTextFile(path, value.dump(2) + "\n");
}

void refuseOutputsOverInputs(const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outFiles,
                             const std::vector<std::string>& outDirs) {
  for (const auto& file : outFiles)
    if (file != "-") refuseOutputOverInputs(file, inputs);
  for (const auto& dir : outDirs) refuseDirectoryOverInputs(dir, inputs);
}

ImageSize parseSize(const std::string& text, const std::string& option) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    throw UserError(concat(option, " '", text, "': expected WxH, e.g. 256x256"));
  const ImageSize size{w, h};
  validateImageSize(size, option + " " + text);
  return size;
}

namespace {
/// The parameters of options whose flag is not named after them.
std::map<const CLI::Option*, std::vector<std::string>>& taggedParameters() {
  static std::map<const CLI::Option*, std::vector<std::string>> tags;
  return tags;
}

bool sameWords(std::string flag, const std::string& parameter) {
  std::replace(flag.begin(), flag.end(), '-', ' ');
  return flag.size() == parameter.size() &&
         std::equal(flag.begin(), flag.end(), parameter.begin(),
                    [](char a, char b) { return ::tolower(a) == ::tolower(b); });
}
}  // namespace

void nameParameters(CLI::App& command,
                    const std::map<std::string, std::vector<std::string>>& flagParameters) {
  for (const auto& [flag, parameters] : flagParameters)
    taggedParameters()[command.get_option(flag)] = parameters;
}

std::string messageWithFlag(const ParameterError& error, const CLI::App& app) {
  const CLI::App* command = &app;
  while (!command->get_subcommands().empty()) command = command->get_subcommands().front();
  for (const CLI::Option* option : command->get_options()) {
    const auto tag = taggedParameters().find(option);
    const bool sets = tag != taggedParameters().end()
                          ? std::count(tag->second.begin(), tag->second.end(), error.parameter())
                          : !option->get_lnames().empty() &&
                                sameWords(option->get_lnames().front(), error.parameter());
    if (sets) return error.messageFor("--" + option->get_lnames().front());
  }
  return error.what();
}

StudyLog stderrLog(const std::string& prefix, bool quiet) {
  if (quiet) return {};
  return [prefix](const std::string& line) { std::cerr << prefix << ": " << line << std::endl; };
}

void printStudy(const StudyOutput& output, const CommonOptions& common) {
  if (!common.quiet) std::cout << output.summary << std::flush;
  writeJson(common.jsonPath, output.json);
}

namespace {
bool isImageFile(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".exr" || ext == ".hdr" || ext == ".pfm" || ext == ".tif" || ext == ".tiff";
}
}  // namespace

std::vector<std::string> expandEnvironments(const std::vector<std::string>& specs) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const auto& spec : specs) {
    if (!isAnalyticEnvironment(spec) && fs::is_directory(spec)) {
      std::vector<std::string> files;
      for (const auto& entry : fs::directory_iterator(spec))
        if (entry.is_regular_file() && isImageFile(entry.path()))
          files.push_back(entry.path().string());
      if (files.empty())
        throw ParameterError("environment", spec, "the directory holds no .exr/.hdr maps");
      std::sort(files.begin(), files.end());
      out.insert(out.end(), files.begin(), files.end());
    } else {
      out.push_back(spec);
    }
  }
  return out;
}

}  // namespace acpca::cli
