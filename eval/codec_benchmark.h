#pragma once
// `bench codecs`: one frame encoded in each of a batch's formats by imageio's
// own encoders (imageio/png_encoder.h, exr_encoder.h) against OpenImageIO's
// writer on the same values, one core each, beside the machine's streaming
// read: the per-frame cost a batch's writing threads pay, as ms and ratios.
#include <string>

#include "core/study_output.h"

namespace acpca {

struct CodecBenchmarkOptions {
  std::string image;      ///< a frame to encode (EXR or anything OpenImageIO reads)
  std::string directory;  ///< where the files are written and removed
  int repeats = 15;       ///< encodings of each case; the median counts
  double streamGiB = 0.5;
};

/// Table (format, ms of imageio's encoder, of OpenImageIO's, their ratio,
/// bytes of each, ms of the whole frame's encoding from linear floats) as
/// text and JSON.
StudyOutput runCodecBenchmark(const CodecBenchmarkOptions& options);

}  // namespace acpca
