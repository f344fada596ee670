#include "web/site_files.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// The files an earlier export listed in `directory` (empty when none).
std::set<std::string> listedFiles(const fs::path& directory) {
  std::set<std::string> listed;
  const fs::path list = directory / kSiteListName;
  if (!fs::exists(list)) return listed;
  std::ifstream in(list);
  const nlohmann::json json = nlohmann::json::parse(in, nullptr, false);
  if (json.is_discarded() || !json.is_object() || json.value("format", "") != kSiteFormat ||
      !json.contains("files") || !json["files"].is_array())
    throw UserError(concat(list.string(), ": not a list of a web export's files (", kSiteFormat,
                           "); choose another --out"));
  for (const auto& name : json["files"])
    if (name.is_string()) listed.insert(name.get<std::string>());
  listed.insert(kSiteListName);
  return listed;
}

}  // namespace

void refuseForeignSiteFiles(const std::string& directory) {
  const fs::path dir(directory);
  if (!fs::exists(dir)) return;
  if (!fs::is_directory(dir))
    throw UserError(concat(directory, ": --out names a file, not a directory"));
  const std::set<std::string> listed = listedFiles(dir);
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_directory()) continue;
    const std::string name = fs::relative(entry.path(), dir).generic_string();
    if (!listed.count(name))
      throw UserError(concat(directory, " holds ", name,
                             ", which no web export wrote: choose an empty or new --out"));
  }
}

SiteWriter::SiteWriter(std::string directory) : directory_(std::move(directory)) {
  createOutputDirectory(directory_);
}

void SiteWriter::write(const std::string& name, const void* bytes, size_t size) {
  const fs::path path = fs::path(directory_) / name;
  createOutputDirectory(path.parent_path().string());
  AtomicOutput output(path.string());
  {
    std::ofstream out(output.tempPath(), std::ios::binary);
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    out.close();
    if (!out) throw WriteError(concat("cannot write ", path.string()));
  }
  output.commit();
  files_.push_back(name);
  bytes_ += static_cast<long long>(size);
}

void SiteWriter::finish() {
  const std::set<std::string> before = listedFiles(directory_);
  const std::set<std::string> now(files_.begin(), files_.end());
  for (const std::string& name : before)
    if (name != kSiteListName && !now.count(name)) fs::remove(fs::path(directory_) / name);
  const nlohmann::json list = {{"format", kSiteFormat}, {"files", files_}};
  writeTextFile((fs::path(directory_) / kSiteListName).string(), list.dump(1) + "\n");
}

}  // namespace acpca
