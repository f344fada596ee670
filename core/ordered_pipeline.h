#pragma once
// The one streaming pattern of the project: a serial stage produces work items
// in order (reading a file, or numbering bands), a parallel stage processes
// them, and a serial stage consumes them in the same order. At most `tokens`
// items are in flight, each in its own reused slot, so memory stays bounded and
// the consumer sees the same sequence for any thread count.
#include <tbb/parallel_pipeline.h>

#include <vector>

namespace acpca {

/// produce(slot) fills the slot and returns false when there is nothing left;
/// process(slot) runs in parallel; consume(slot) runs in order.
template <typename Slot, typename Produce, typename Process, typename Consume>
void runOrderedPipeline(int tokens, Produce&& produce, Process&& process, Consume&& consume) {
  std::vector<Slot> slots(static_cast<size_t>(tokens));
  size_t next = 0;
  tbb::parallel_pipeline(tokens,
                         tbb::make_filter<void, Slot*>(tbb::filter_mode::serial_in_order,
                                                       [&](tbb::flow_control& fc) -> Slot* {
                                                         // Items finish in order and at most
                                                         // `tokens` are in flight, so a slot is
                                                         // free when its turn comes again.
                                                         Slot* slot = &slots[next++ % slots.size()];
                                                         if (!produce(*slot)) {
                                                           fc.stop();
                                                           return nullptr;
                                                         }
                                                         return slot;
                                                       }) &
                             tbb::make_filter<Slot*, Slot*>(tbb::filter_mode::parallel,
                                                            [&](Slot* slot) {
                                                              process(*slot);
                                                              return slot;
                                                            }) &
                             tbb::make_filter<Slot*, void>(tbb::filter_mode::serial_in_order,
                                                           [&](Slot* slot) { consume(*slot); }));
}

}  // namespace acpca
