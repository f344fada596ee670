#pragma once
// A group of frames relit into composed images: a model's frames shaded
// straight into their images after one projection, a transport's rows added
// onto the background, timing mode's repeats; and the pixel buffers frames
// are composed in, handed back once written.
#include <functional>
#include <mutex>
#include <vector>

#include "dataset/batch_relight.h"
#include "relight/image_composer.h"
#include "relight/relight_source.h"

namespace acpca {

/// Frames encoded, written or waiting for their turn to commit at once: the
/// memory a batch holds beyond the group it relights.
inline constexpr size_t kFramesInFlight = 8;

/// Frames' pixel buffers, handed back by the writing threads once a frame is
/// encoded and taken again for the next: a fresh 1024x1024 frame is 12 MB of
/// pages the kernel zeroes and the vector zeroes again (a third of the
/// background stage). Nothing is read before the background writes it.
class FrameBuffers {
 public:
  std::vector<float> take(size_t values) {
    std::vector<float> buffer;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) buffer = std::move(free_.back()), free_.pop_back();
    }
    buffer.resize(values);  // the same size as before: nothing to fill
    return buffer;
  }
  void giveBack(std::vector<float>&& buffer) {
    const std::lock_guard<std::mutex> lock(mutex_);
    // As many as can be in flight at once, and the group relighting.
    if (free_.size() < 2 * kFramesInFlight) free_.push_back(std::move(buffer));
  }

 private:
  std::mutex mutex_;
  std::vector<std::vector<float>> free_;
};

/// One group relit into composed images (`backgroundOf(k, pixels)` puts frame
/// k's background there first), each handed to `done` with its relight time
/// (which may move the pixels away). A model shades its frames straight into
/// their images after one projection of the group; a transport's rows (and
/// timing mode's) are added onto the background.
void relightGroupImages(const RelightSource& source, const ImageComposer& composer,
                        FrameBuffers& buffers, const std::vector<LatticeLighting>& lightings,
                        int channels, const std::function<void(size_t, float*)>& backgroundOf,
                        int timingRepeats, std::vector<double>& msPerFrame, BatchStages& stages,
                        const std::function<void(size_t, std::vector<float>&, double)>& done);

}  // namespace acpca
