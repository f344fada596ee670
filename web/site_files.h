#pragma once
// The files of a web export: each written under a temporary name and renamed,
// and the list of them (site.json) that lets a later export rewrite its own
// directory but no other.
#include <string>
#include <vector>

namespace acpca {

inline constexpr const char* kSiteListName = "site.json";
inline constexpr const char* kSiteFormat = "adaptive-cpca web page";

/// Throws UserError naming `directory` and the first file in it that no
/// earlier export wrote (nothing is listed in its site.json); an absent or
/// empty directory passes.
void refuseForeignSiteFiles(const std::string& directory);

/// Writes each file of the site in turn, then the list of them.
class SiteWriter {
 public:
  explicit SiteWriter(std::string directory);
  void write(const std::string& name, const void* bytes, size_t size);
  void write(const std::string& name, const std::string& text) {
    write(name, text.data(), text.size());
  }
  /// Writes site.json, listing every file written, and removes what an
  /// earlier export listed that this one did not write.
  void finish();
  long long bytes() const { return bytes_; }
  const std::vector<std::string>& files() const { return files_; }

 private:
  std::string directory_;
  std::vector<std::string> files_;
  long long bytes_ = 0;
};

}  // namespace acpca
