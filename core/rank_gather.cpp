#include "core/rank_gather.h"

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "core/error.h"
#include "core/ranks.h"

namespace acpca::ranks {

namespace {

constexpr int kTags = 32767;  // MPI guarantees tags below it; ranks reserves 32767

template <typename T>
void sendValues(int to, int tag, const std::vector<T>& values) {
  if constexpr (std::is_same_v<T, float>)
    send(to, tag, values);
  else
    sendBytes(to, tag, values);
}

template <typename T>
std::vector<T> receiveValues(int from, int tag) {
  if constexpr (std::is_same_v<T, float>)
    return receive(from, tag);
  else
    return receiveBytes(from, tag);
}

}  // namespace

int ownerOf(long long item) {
  return static_cast<int>(item % count());
}

std::vector<long long> itemsOfThisRank(long long count) {
  std::vector<long long> mine;
  for (long long i = rank(); i < count; i += ranks::count()) mine.push_back(i);
  return mine;
}

template <typename T>
Gather<T>::Gather(long long count, GatherOrder order, Deliver deliver, int tag)
    : count_(count), order_(order), deliver_(std::move(deliver)), tag_(tag) {
  ACPCA_CHECK(tag >= 0 && tag < kTags, "gather tag ", tag);
  if (rank() != 0 || order != GatherOrder::Arrival) return;
  const long long others = count - (count + ranks::count() - 1) / ranks::count();  // not rank 0's
  if (others > 0) receiver_ = std::thread([this, others] { receiveArrivals(others); });
}

template <typename T>
Gather<T>::~Gather() {
  stop_ = true;
  if (receiver_.joinable()) receiver_.join();
}

template <typename T>
void Gather<T>::receiveArrivals(long long others) {
  // A message is the item's index, then its values, from the same sender
  // under the same tag (MPI keeps their order).
  try {
    while (others > 0 && !stop_) {
      if (!pending(tag_)) {
        sleepBetweenPolls();
        continue;
      }
      int from = 0;
      const std::vector<char> index = receiveBytesFromAny(tag_, from);
      std::uint64_t item = 0;
      ACPCA_CHECK(index.size() == sizeof item, "gather message from rank ", from, " has no index");
      std::memcpy(&item, index.data(), sizeof item);
      ACPCA_CHECK(static_cast<long long>(item) < count_ && ownerOf(item) == from, "item ", item,
                  " from rank ", from);
      std::vector<T> values = receiveValues<T>(from, tag_);
      deliver_(static_cast<long long>(item), values);
      --others;
    }
  } catch (...) {
    failure_ = std::current_exception();
  }
}

template <typename T>
void Gather<T>::deliverOthersBefore(long long end) {
  for (; next_ < end; ++next_)
    if (ownerOf(next_) != 0) {
      std::vector<T> values = receiveValues<T>(ownerOf(next_), (tag_ + next_) % kTags);
      deliver_(next_, values);
    }
}

template <typename T>
void Gather<T>::put(long long item, std::vector<T>& values) {
  ACPCA_CHECK(item >= 0 && item < count_ && ownerOf(item) == rank(), "item ", item,
              " is not this rank's");
  if (rank() == 0) {
    if (order_ == GatherOrder::ItemOrder) {
      deliverOthersBefore(item);
      next_ = item + 1;
    }
    deliver_(item, values);
    return;
  }
  if (order_ == GatherOrder::ItemOrder) {
    sendValues(0, static_cast<int>((tag_ + item) % kTags), values);
  } else {
    std::vector<char> index(sizeof(std::uint64_t));
    const std::uint64_t i = static_cast<std::uint64_t>(item);
    std::memcpy(index.data(), &i, sizeof i);
    sendBytes(0, tag_, index);
    sendValues(0, tag_, values);
  }
}

template <typename T>
void Gather<T>::finish() {
  if (rank() != 0) return;
  if (order_ == GatherOrder::ItemOrder) deliverOthersBefore(count_);
  if (receiver_.joinable()) receiver_.join();
  if (failure_) std::rethrow_exception(failure_);
}

template class Gather<float>;
template class Gather<char>;

}  // namespace acpca::ranks
