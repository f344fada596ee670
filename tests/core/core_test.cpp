// The shared helpers: tables as CSV and JSON, enum name tables, parameter
// errors, the ordered pipeline, statistics and atomic text files.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include <tbb/global_control.h>

#include "core/atomic_file.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/huge_pages.h"
#include "core/input_guard.h"
#include "core/interrupt_cleanup.h"
#include "core/ordered_pipeline.h"
#include "core/resources.h"
#include "core/statistics.h"
#include "core/table.h"
#include "core/text.h"
#include "core/warning.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

/// Sets a soft resource limit while it lives.
class SoftLimit {
 public:
  SoftLimit(int resource, rlim_t value) : resource_(resource) {
    getrlimit(resource_, &saved_);
    rlimit limit = saved_;
    limit.rlim_cur = value;
    setrlimit(resource_, &limit);
  }
  ~SoftLimit() { setrlimit(resource_, &saved_); }

 private:
  int resource_;
  rlimit saved_{};
};

std::string refusal(const ResourceNeed& need) {
  try {
    requireResources(need, false);
  } catch (const UserError& e) {
    return e.what();
  }
  return "";
}

TEST(Resources, NeedsBeyondTheDiskTheFileLimitOrTheMemoryAreRefusedWithBothFigures) {
  test::TempDir dir;
  ResourceNeed need;
  need.what = "the test's output";
  need.diskDirectory = dir.path().string();
  need.diskAdvice = "write less";
  EXPECT_EQ(refusal(need), "") << "needing nothing always fits";
  need.diskBytes = 1LL << 50;  // a pebibyte
  const std::string disk = refusal(need);
  EXPECT_NE(disk.find("needs up to 1024.00 TiB on disk"), std::string::npos) << disk;
  EXPECT_NE(disk.find(" free; write less; forcing the run skips this check"), std::string::npos)
      << disk;
  EXPECT_NO_THROW(requireResources(need, true)) << "force goes past";
  need.diskBytes = 3 << 20;
  {
    const SoftLimit files(RLIMIT_FSIZE, 1 << 20);
    EXPECT_EQ(fileSizeLimit(), 1 << 20);
    const std::string file = refusal(need);
    EXPECT_NE(file.find("files of up to 3.00 MiB"), std::string::npos) << file;
    EXPECT_NE(file.find("at most 1.00 MiB (ulimit -f)"), std::string::npos) << file;
  }
  EXPECT_EQ(refusal(need), "") << "3 MiB fits once the limit is gone";
  need.diskBytes = 0;
  need.memoryBytes = 1LL << 60;
  need.memoryAdvice = "hold less";
  const std::string memory = refusal(need);
  EXPECT_NE(memory.find("of memory, and"), std::string::npos) << memory;
  EXPECT_NE(memory.find("are available; hold less"), std::string::npos) << memory;
  EXPECT_GT(freeDiskBytes(dir.path().string()), 0);
}

TEST(Resources, AnAddressSpaceLimitBoundsTheMemoryAvailable) {
  std::ifstream statm("/proc/self/statm");
  long long pages = 0;
  statm >> pages;
  const long long mapped = pages * sysconf(_SC_PAGESIZE);
  const long long before = availableMemoryBytes();
  {
    const SoftLimit addressSpace(RLIMIT_AS, static_cast<rlim_t>(mapped + (256LL << 20)));
    const long long within = availableMemoryBytes();
    EXPECT_LE(within, 256LL << 20);
    EXPECT_GT(within, 128LL << 20) << "what is left under the limit, not zero";
  }
  EXPECT_EQ(availableMemoryBytes() > (256LL << 20), before > (256LL << 20));
}

TEST(InputGuard, TheSameFileByAnyNameIsRefusedAndADirectoryHoldingItToo) {
  test::TempDir dir;
  namespace fs = std::filesystem;
  const std::string input = dir.file("in.h5");
  std::ofstream(input) << "data";
  fs::create_hard_link(input, dir.file("hard.h5"));
  fs::create_symlink(input, dir.file("soft.h5"));
  fs::create_directories(dir.file("sub/deeper"));
  const auto refused = [&](const std::string& out) {
    try {
      refuseOutputOverInputs(out, {"sky", input});
    } catch (const UserError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused(input).find("is the input"), std::string::npos);
  EXPECT_NE(refused(dir.file("sub/../in.h5")).find("is the input"), std::string::npos);
  EXPECT_NE(refused(dir.file("hard.h5")).find("is a hard link of the input"), std::string::npos);
  EXPECT_NE(refused(dir.file("soft.h5")).find("is a symbolic link to the input"),
            std::string::npos);
  EXPECT_EQ(refused(dir.file("new.h5")), "") << "a file not there yet replaces nothing";
  EXPECT_THROW(refuseDirectoryOverInputs(dir.path().string(), {input}), UserError);
  EXPECT_THROW(refuseDirectoryOverInputs(dir.path().string(), {dir.file("sub/deeper")}), UserError);
  EXPECT_NO_THROW(refuseDirectoryOverInputs(dir.file("sub"), {input}));
  EXPECT_NO_THROW(refuseDirectoryOverInputs(dir.file("elsewhere"), {input}));
}

TEST(InterruptCleanup, AtomicOutputsAreRegisteredWhileTheyAreWritten) {
  test::TempDir dir;
  const int before = interrupt::registeredTemporaries();
  {
    AtomicOutput a(dir.file("a.txt")), b(dir.file("b.txt"));
    EXPECT_EQ(interrupt::registeredTemporaries(), before + 2);
    std::ofstream(a.tempPath()) << "a";
    a.commit();
    EXPECT_EQ(interrupt::registeredTemporaries(), before + 1) << "committed: no longer removed";
  }
  EXPECT_EQ(interrupt::registeredTemporaries(), before) << "abandoned: removed and released";
}

TEST(Table, CsvAndJsonHoldTheSameRows) {
  Table t({"name", "value", "count"});
  t.add({std::string("a b"), 0.5, 3LL});
  t.add({std::string("x,\"y\""), NAN, -1LL});
  EXPECT_EQ(t.csv(), "name,value,count\n\"a b\",0.5,3\n\"x,\"\"y\"\"\",,-1\n");
  const auto j = t.json();
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["name"], "a b");
  EXPECT_EQ(j[0]["value"], 0.5);
  EXPECT_EQ(j[0]["count"], 3);
  EXPECT_TRUE(j[1]["value"].is_null());
  EXPECT_THROW(t.add({1.0}), std::logic_error);  // one cell per column
}

TEST(Table, WritesAtomicallyAndNamesAPathItCannotWrite) {
  test::TempDir dir;
  Table t({"a"});
  t.add({1.0});
  t.writeCsv(dir.file("t.csv"));
  std::ifstream in(dir.file("t.csv"));
  std::string all((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(all, "a\n1\n");
  try {
    t.writeCsv(dir.file("missing/t.csv"));
    FAIL() << "wrote into a directory that does not exist";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

enum class Colour { Red, Green };
constexpr EnumNames<Colour, 2> kColours{"colour",
                                        {{{Colour::Red, "red"}, {Colour::Green, "green"}}}};

TEST(EnumNames, ParsesPrintsAndRefusesByName) {
  EXPECT_EQ(kColours.parse("green"), Colour::Green);
  EXPECT_STREQ(kColours.name(Colour::Red), "red");
  try {
    kColours.parse("blue");
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.parameter(), "colour");
    EXPECT_EQ(e.value(), "blue");
    EXPECT_STREQ(e.what(), "colour 'blue': is not one of red, green");
    EXPECT_EQ(e.messageFor("--colour"), "--colour 'blue': is not one of red, green");
  }
}

TEST(HeldWarnings, HoldTheirThreadsWarningsNestedAndLeaveOtherThreadsAlone) {
  std::vector<std::string> reported;
  const WarningHandler previous =
      setWarningHandler([&](const std::string& w) { reported.push_back(w); });
  {
    HeldWarnings outer;
    warn("a");
    {
      HeldWarnings inner;
      warn("b");
      std::thread([] { warn("elsewhere"); }).join();  // no holder on that thread
      EXPECT_EQ(inner.take(), std::vector<std::string>{"b"});
    }
    warn("c");
    EXPECT_EQ(outer.take(), (std::vector<std::string>{"a", "c"}));
    warn("dropped");
  }
  warn("d");
  setWarningHandler(previous);
  EXPECT_EQ(reported, (std::vector<std::string>{"elsewhere", "d"}));
}

TEST(OrderedPipeline, ConsumesInOrderForAnyThreadCount) {
  for (int threads : {1, 2, 4}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    struct Slot {
      int index = 0, square = 0;
    };
    int next = 0;
    std::vector<int> seen;
    runOrderedPipeline<Slot>(
        3,
        [&](Slot& s) {
          if (next == 100) return false;
          s.index = next++;
          return true;
        },
        [](Slot& s) { s.square = s.index * s.index; },
        [&](Slot& s) {
          EXPECT_EQ(s.square, s.index * s.index);
          seen.push_back(s.index);
        });
    ASSERT_EQ(seen.size(), 100u);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(seen[i], i);
  }
}

TEST(HugePages, LargeVectorsAreAlignedToHugePagesAndHoldTheirValues) {
  // Below the threshold: the ordinary heap; above it: 2 MiB-aligned storage.
  // Either way a vector behaves as any other (growth copies, values kept).
  HugePageVector<float> small(1000, 1.5f);
  EXPECT_EQ(small.size(), 1000u);
  HugePageVector<std::int8_t> large;
  for (int i = 0; i < (9 << 20); ++i) large.push_back(static_cast<std::int8_t>(i % 251 - 125));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(large.data()) % (std::uintptr_t(2) << 20), 0u);
  for (int i = 0; i < (9 << 20); i += 4099)
    ASSERT_EQ(large[i], static_cast<std::int8_t>(i % 251 - 125)) << i;
  HugePageVector<std::int8_t> copy = large;
  EXPECT_EQ(copy, large);
  large.clear();
  large.shrink_to_fit();
  EXPECT_EQ(copy.size(), std::size_t(9) << 20);
}

TEST(Statistics, MedianAndRelativeL2) {
  EXPECT_EQ(median({3, 1, 2}), 2);
  EXPECT_EQ(median({}), 0);
  EXPECT_NEAR(relativeL2({1, 2, 2}, {1, 2, 3}), 1 / std::sqrt(14.0), 1e-12);
  EXPECT_EQ(formatted("%d-%s", 7, "x"), "7-x");
  EXPECT_EQ(formatBytes(1536), "1.50 KiB");
}

}  // namespace
}  // namespace acpca
