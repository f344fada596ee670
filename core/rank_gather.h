#pragma once
// "Deal round robin, gather at rank 0": the one protocol by which work spread
// over the ranks of an MPI job comes back to the rank that writes it (the
// precompute's bands, a batch's frames, the build's tiles). Item i is made by
// rank i mod K; rank 0 gets every item, its own and the others', through one
// callback. Without MPI (or with one rank) every item is rank 0's and the
// callback sees each put at once.
#include <atomic>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace acpca::ranks {

/// The rank that makes item i of a job dealt round robin.
int ownerOf(long long item);
/// The items of [0, count) this rank makes, increasing.
std::vector<long long> itemsOfThisRank(long long count);

/// How rank 0 takes the other ranks' items.
enum class GatherOrder {
  /// In item order, on the thread that puts rank 0's own items (before its
  /// own item i, every other rank's item below i): for one file written in order.
  ItemOrder,
  /// As they arrive, on a receiving thread of rank 0's, while it makes its
  /// own: for items that are files of their own. The callback must then be
  /// safe to run beside rank 0's own work, and must not call MPI.
  Arrival,
};

/// One gather. A sender's put waits until rank 0 takes its item, so at most
/// one message per sender is in flight; the framing (which item a message
/// holds) is this class's. Only one thread per rank calls it.
template <typename T>  // float or char
class Gather {
 public:
  /// Gets each item's values; it may move them away (a batch keeps a frame's
  /// pixels without copying them).
  using Deliver = std::function<void(long long item, std::vector<T>& values)>;
  /// `tag` keeps this gather's messages apart from others' (0 <= tag < 32767;
  /// item order uses the tags from `tag` on, modulo 32767).
  Gather(long long count, GatherOrder order, Deliver deliver, int tag = 0);
  /// Stops an arrival receiver still waiting (after a failure elsewhere).
  ~Gather();
  Gather(const Gather&) = delete;
  Gather& operator=(const Gather&) = delete;

  /// Hands over this rank's `item` (rank 0: delivers it, after every earlier
  /// item of the others in item order; other ranks: send it to rank 0).
  void put(long long item, std::vector<T>& values);
  /// Rank 0: delivers every item not yet delivered, waiting for them, and
  /// rethrows what failed on the receiving thread; other ranks: nothing.
  void finish();

 private:
  void deliverOthersBefore(long long end);
  void receiveArrivals(long long others);

  long long count_;
  GatherOrder order_;
  Deliver deliver_;
  int tag_;
  long long next_ = 0;  ///< item order: the first item rank 0 has not delivered
  std::thread receiver_;
  std::atomic<bool> stop_{false};
  std::exception_ptr failure_;
};

extern template class Gather<float>;
extern template class Gather<char>;

}  // namespace acpca::ranks
