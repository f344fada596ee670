// A program for the gather tests (tests/cli/mpi_test.cpp), run under mpirun:
// `gather_probe COUNT item|arrival float|char KILL OUT`. Every rank makes its
// items (item i: i + 1 values, each a function of i and its place), rank
// KILL's owner dies as it starts item KILL (-1: none), and rank 0 checks that
// every item arrived once, whole, and in item order where asked; then writes
// "gathered COUNT" to OUT. Exit 0 when all held, 2 when one did not.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/rank_gather.h"
#include "core/ranks.h"

namespace {

template <typename T>
T valueOf(long long item, size_t k) {
  return static_cast<T>((item * 7 + static_cast<long long>(k)) % 101);
}

template <typename T>
int run(long long count, acpca::ranks::GatherOrder order, long long kill, const char* out) {
  std::vector<int> seen(static_cast<size_t>(count), 0);
  long long last = -1;
  bool ok = true;
  acpca::ranks::Gather<T> gather(count, order, [&](long long item, std::vector<T>& values) {
    bool whole = values.size() == static_cast<size_t>(item + 1);
    for (size_t k = 0; whole && k < values.size(); ++k) whole = values[k] == valueOf<T>(item, k);
    if (!whole) std::fprintf(stderr, "item %lld arrived damaged\n", item), ok = false;
    if (order == acpca::ranks::GatherOrder::ItemOrder && item != last + 1)
      std::fprintf(stderr, "item %lld arrived after %lld\n", item, last), ok = false;
    last = item;
    ++seen[static_cast<size_t>(item)];
  });
  for (long long item : acpca::ranks::itemsOfThisRank(count)) {
    if (item == kill) std::raise(SIGKILL);
    std::vector<T> values(static_cast<size_t>(item + 1));
    for (size_t k = 0; k < values.size(); ++k) values[k] = valueOf<T>(item, k);
    gather.put(item, values);
  }
  gather.finish();
  if (acpca::ranks::rank() != 0) return 0;
  for (long long i = 0; i < count; ++i)
    if (seen[static_cast<size_t>(i)] != 1)
      std::fprintf(stderr, "item %lld arrived %d times\n", i, seen[static_cast<size_t>(i)]),
          ok = false;
  if (!ok) return 2;
  acpca::writeTextFile(out, "gathered " + std::to_string(count) + "\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  acpca::ranks::Session mpi(argc, argv);
  if (argc != 6) {
    std::fprintf(stderr, "usage: gather_probe COUNT item|arrival float|char KILL OUT\n");
    return 1;
  }
  const long long count = std::atoll(argv[1]), kill = std::atoll(argv[4]);
  const auto order = std::string(argv[2]) == "arrival" ? acpca::ranks::GatherOrder::Arrival
                                                       : acpca::ranks::GatherOrder::ItemOrder;
  const int code = std::string(argv[3]) == "char" ? run<char>(count, order, kill, argv[5])
                                                  : run<float>(count, order, kill, argv[5]);
  return code == 0 ? 0 : acpca::ranks::abortAll(code);
}
