// Tars as a shard writes them, read back with libarchive's reader: members
// in the order given with their bytes, fixed times and owners (so the same
// files make the same tar, byte for byte), and nothing in place when a
// member cannot be read.
#include <gtest/gtest.h>

#include <archive.h>
#include <archive_entry.h>

#include "core/error.h"
#include "dataset/tar_archive.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;

struct ReadMember {
  std::string name, bytes;
  long long mtime, uid, gid;
  int perm;
};

std::vector<ReadMember> readTar(const std::string& path) {
  archive* tar = archive_read_new();
  archive_read_support_format_tar(tar);
  EXPECT_EQ(archive_read_open_filename(tar, path.c_str(), 10240), ARCHIVE_OK) << path;
  std::vector<ReadMember> members;
  archive_entry* entry;
  while (archive_read_next_header(tar, &entry) == ARCHIVE_OK) {
    std::string bytes(static_cast<size_t>(archive_entry_size(entry)), '\0');
    archive_read_data(tar, bytes.data(), bytes.size());
    members.push_back({archive_entry_pathname(entry), bytes, archive_entry_mtime(entry),
                       archive_entry_uid(entry), archive_entry_gid(entry),
                       static_cast<int>(archive_entry_perm(entry))});
  }
  archive_read_free(tar);
  return members;
}

TEST(TarArchive, MembersComeBackInOrderWithFixedTimesAndOwners) {
  TempDir dir;
  std::string big(70000, '\0');
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(i * 31 % 251);
  test::writeFile(dir.file("a.bin"), big);
  test::writeFile(dir.file("b.json"), "{\"frame\": 7}\n");
  test::writeFile(dir.file("empty"), "");
  const std::vector<TarMember> members{{"00007.exr", dir.file("a.bin")},
                                       {"00007.json", dir.file("b.json")},
                                       {"e", dir.file("empty")}};
  writeTar(dir.file("one.tar"), members);
  const auto read = readTar(dir.file("one.tar"));
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(read[0].name, "00007.exr");
  EXPECT_EQ(read[0].bytes, big);
  EXPECT_EQ(read[1].bytes, "{\"frame\": 7}\n");
  EXPECT_EQ(read[2].bytes, "");
  for (const auto& m : read) {
    EXPECT_EQ(m.mtime, 0);
    EXPECT_EQ(m.uid, 0);
    EXPECT_EQ(m.gid, 0);
    EXPECT_EQ(m.perm, 0644);
  }
  // Made again later: the same bytes.
  writeTar(dir.file("two.tar"), members);
  EXPECT_EQ(test::readFile(dir.file("one.tar")), test::readFile(dir.file("two.tar")));
}

TEST(TarArchive, AMemberThatCannotBeReadLeavesNoTar) {
  TempDir dir;
  test::writeFile(dir.file("a"), "a");
  try {
    writeTar(dir.file("x.tar"), {{"a", dir.file("a")}, {"gone", dir.file("gone")}});
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("gone")), std::string::npos) << e.what();
  }
  EXPECT_FALSE(test::fs::exists(dir.file("x.tar")));
  for (const auto& entry : test::fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos);
}

}  // namespace
}  // namespace acpca
