#pragma once
// The run-time hot path (docs/design.md section 6, [Mahajan07] eq. 17): per frame,
//   L_g = V_g^T L            (N x 3, over the directions some pixel sees)
//   L_i = W_i^T L_g          (n_i x 3 per cluster, plus mu_i . L_g with a mean)
//   b_p = albedo_p (u_p . L_i)
// Three TBB phases: L_g, every cluster's L_i, then the pixels span by span.
// A cluster's rows lie all over the image, so shading cluster by cluster wrote
// pixels all over it, each write fetching its cache line from memory (a quarter
// of a frame at 1024x1024). Chunks of 16 rows are instead stored and shaded in
// spans of 8,192 rows (by their first row; packed_model.h), so a thread's
// writes stay in a few hundred KB and its reads are one sequential stream. Each value is computed
// by one task in a fixed order, so the image is the same for any thread count. All memory is
// allocated when the relighter is built; a frame allocates nothing.
#include <memory>
#include <vector>

#include "lighting/environment.h"
#include "relight/packed_model.h"

namespace acpca {

class ModelRelighter {
 public:
  /// Repacks the model's coefficients for the SIMD loop (k-major chunks of 16
  /// rows per cluster); the model may be released afterwards.
  explicit ModelRelighter(const Model& model);
  /// Shares a model packed before: relighters of one model, each with its own
  /// per-frame scratch, hold its data once.
  explicit ModelRelighter(std::shared_ptr<const PackedModel> packed);

  /// Uses only each cluster's first min(n_i, k) bases ([Lehtinen03]'s quality/speed
  /// trade: PCA bases come in order of importance). k < 0: all of them.
  void setMaxRank(int k);
  /// Uses the first ceil(fraction * n_i) bases of each cluster, fraction in [0, 1].
  void setRankFraction(double fraction);

  /// Relights one lighting (3 l values, RGB per texel) into rgb: 3 floats per
  /// occupied row, albedo applied, in the model's row order.
  void relight(const LatticeLighting& lighting, float* rgb);
  std::vector<float> relight(const LatticeLighting& lighting);
  /// Relights straight into an image (width x height pixels of `channels`
  /// floats, row-major): each occupied pixel gets coverage x its relit value
  /// added to its first three channels, the caller having put the background,
  /// weighted by 1 - coverage, there first (ImageComposer::background).
  void relightInto(const LatticeLighting& lighting, float* pixels, int channels);

  /// A group of frames: lightGroup projects every lighting onto the global
  /// basis and the cluster bases at once, reading V_g and the bases once for
  /// the group instead of once a frame (what dominates small images); then
  /// shadeFrame / shadeFrameInto shade frame k of the group, as relight /
  /// relightInto would, bit for bit. A rank limit set in between applies from
  /// the next group.
  void lightGroup(const std::vector<LatticeLighting>& lightings);
  void lightGroup(const LatticeLighting* const* lightings, size_t frames);
  size_t groupFrames() const { return groupFrames_; }
  void shadeFrame(size_t frame, float* rgb) const;
  void shadeFrameInto(size_t frame, float* pixels, int channels) const;

  /// Bases each cluster uses at the current rank limit.
  const std::vector<int>& activeRanks() const { return activeRanks_; }
  const TransportHeader& geometry() const { return m_.geometry; }
  long long rows() const { return m_.rows(); }
  const std::shared_ptr<const PackedModel>& packed() const { return packed_; }
  /// Bytes of model data one frame reads at the current rank limit: bases,
  /// coefficients (with chunk padding), row indices and albedo.
  /// In a group of frames (lightGroup), V_g and the bases count once a group.
  long long bytesPerFrame(size_t groupFrames = 1) const;
  /// Multiply-adds per pixel at the current rank limit (eq. 18, per channel).
  double costPerPixel() const;

 private:
  /// Where a frame's values go: rgb[stride * target[lane] + c] (= or += weight).
  struct Output {
    float* values;
    int stride;
    bool image;  ///< add coverage-weighted values at pixel indices, else set rows
  };
  void reserveGroup(size_t frames);
  void lightGlobal(const LatticeLighting* const* lightings, size_t frames);
  template <typename B>
  void lightCluster(int c, const HugePageVector<B>& bases, size_t frames);
  template <typename B>
  void lightClusters(const HugePageVector<B>& bases, size_t frames);
  template <typename T>
  void shadeSpan(long long span, const HugePageVector<T>& coefficients, const Output& out,
                 size_t frame) const;
  template <typename T>
  void shadeSpans(const HugePageVector<T>& coefficients, const Output& out, size_t frame) const;
  void shadeFrame(size_t frame, const Output& out) const;

  std::shared_ptr<const PackedModel> packed_;
  const PackedModel& m_;
  std::vector<int> activeRanks_;
  size_t lightStride_;  ///< floats of one frame's light_, a multiple of 16

  // Per-frame scratch for a group of frames, sized for the largest group yet.
  size_t groupCapacity_ = 0, groupFrames_ = 0;
  std::vector<float> light_;              ///< per frame 3 x |seen|, channel-major
  std::vector<float> globalLighting_;     ///< per frame 3 x N, channel-major
  std::vector<float> globalLightingRgb_;  ///< per frame N x 3, interleaved
  std::vector<float> clusterLighting_;    ///< per frame, per cluster n_i x 3, interleaved
  std::vector<float> meanTerm_;           ///< per frame 3 per cluster
};

}  // namespace acpca
