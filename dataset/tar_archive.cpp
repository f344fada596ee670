#include "dataset/tar_archive.h"

#include <archive.h>
#include <archive_entry.h>

#include <fstream>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"

namespace acpca {

namespace {

struct ArchiveCloser {
  void operator()(archive* a) const { archive_write_free(a); }
};
struct EntryFreer {
  void operator()(archive_entry* e) const { archive_entry_free(e); }
};

std::string readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError(concat(path, ": cannot be read to put in a tar"));
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

void writeTar(const std::string& path, const std::vector<TarMember>& members) {
  AtomicOutput output(path);
  std::unique_ptr<archive, ArchiveCloser> tar(archive_write_new());
  const auto refused = [&](const std::string& what) {
    return WriteError(concat(path, ": ", what, ": ", archive_error_string(tar.get())));
  };
  // ustar: names up to 100 bytes, no pax headers (whose times would vary).
  if (archive_write_set_format_ustar(tar.get()) != ARCHIVE_OK ||
      archive_write_add_filter_none(tar.get()) != ARCHIVE_OK ||
      archive_write_open_filename(tar.get(), output.tempPath().c_str()) != ARCHIVE_OK)
    throw refused("cannot be created");
  for (const TarMember& member : members) {
    const std::string bytes = readWholeFile(member.source);
    std::unique_ptr<archive_entry, EntryFreer> entry(archive_entry_new());
    archive_entry_set_pathname(entry.get(), member.name.c_str());
    archive_entry_set_filetype(entry.get(), AE_IFREG);
    archive_entry_set_perm(entry.get(), 0644);
    archive_entry_set_size(entry.get(), static_cast<la_int64_t>(bytes.size()));
    archive_entry_set_mtime(entry.get(), 0, 0);
    archive_entry_set_uid(entry.get(), 0);
    archive_entry_set_gid(entry.get(), 0);
    if (archive_write_header(tar.get(), entry.get()) != ARCHIVE_OK)
      throw refused(concat("member ", member.name));
    if (archive_write_data(tar.get(), bytes.data(), bytes.size()) !=
        static_cast<la_ssize_t>(bytes.size()))
      throw refused(concat("member ", member.name));
  }
  if (archive_write_close(tar.get()) != ARCHIVE_OK) throw refused("cannot be finished");
  output.commit();
}

}  // namespace acpca
