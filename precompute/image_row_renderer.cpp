#include "precompute/image_row_renderer.h"

#include <algorithm>

namespace acpca {

ImageRowRenderer::ImageRowRenderer(const GBuffer& gbuffer, const ShadowRays& shadows,
                                   const CubeLattice& lattice, Antialiasing mode,
                                   const IndirectLight* indirect)
    : gbuffer_(gbuffer),
      mode_(mode),
      shadows_(shadows),
      indirect_(indirect),
      l_(lattice.size()),
      channels_(indirect ? indirect->settings().channels : 1) {}

ImageRowRenderer::Counts ImageRowRenderer::render(int y, std::vector<float>& out) const {
  const int width = gbuffer_.size.width;
  int rows = 0;
  for (int x = 0; x < width; ++x) rows += hits(x, y) > 0;
  const size_t length = rowLength();
  out.assign(static_cast<size_t>(rows) * length, 0.0f);
  Counts counts;
  int row = 0;
  for (int x = 0; x < width; ++x)
    if (hits(x, y) > 0) renderPixel(x, y, out.data() + row++ * length, counts);
  return counts;
}

void ImageRowRenderer::renderPixel(int x, int y, float* target, Counts& counts) const {
  thread_local std::vector<float> weights;
  sampleWeights(gbuffer_, x, y, mode_, weights);
  counts.supersampled +=
      std::count_if(weights.begin() + 1, weights.end(), [](float w) { return w > 0; }) > 0;
  for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) {
    const PixelSample& ps = gbuffer_.at(x, y, s);
    if (weights[s] > 0) counts.shadowRays += traceDirect(ps, weights[s], target);
  }
  // Light arriving straight from the lattice has its colour in every channel.
  for (int c = 1; c < channels_; ++c) std::copy_n(target, l_, target + c * l_);
  if (indirect_)
    for (int s = 0; s < gbuffer_.samplesPerPixel; ++s)
      if (weights[s] > 0) {
        const auto rays =
            indirect_->add(gbuffer_.at(x, y, s), sampleSeed(x, y, s), weights[s], target);
        counts.pathRays += rays.paths;
        counts.shadowRays += rays.shadow;
      }
}

void ImageRowRenderer::collectCells(int y, std::unordered_map<std::uint64_t, PathVertex>& cells,
                                    std::vector<std::uint64_t>& order) const {
  cells.clear(), order.clear();
  std::vector<float> weights;
  for (int x = 0; x < gbuffer_.size.width; ++x) {
    if (hits(x, y) == 0) continue;
    sampleWeights(gbuffer_, x, y, mode_, weights);
    for (int s = 0; s < gbuffer_.samplesPerPixel; ++s)
      if (weights[s] > 0)
        indirect_->collectCells(gbuffer_.at(x, y, s), sampleSeed(x, y, s), cells, order);
  }
}

int ImageRowRenderer::hits(int x, int y) const {
  int n = 0;
  for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) n += gbuffer_.at(x, y, s).material >= 0;
  return n;
}

std::uint64_t ImageRowRenderer::sampleSeed(int x, int y, int s) const {
  return (static_cast<std::uint64_t>(y) * gbuffer_.size.width + x) * gbuffer_.samplesPerPixel + s;
}

long long ImageRowRenderer::traceDirect(const PixelSample& ps, float weight, float* row) const {
  const Material& m = shadows_.scene().materials()[ps.material];
  const LobeShape shape(m, ps.normal, ps.tangent, ps.toViewer);
  const TexelDirections& dirs = shadows_.directions();
  return shadows_.trace(
      ps.origin, ps.normal, ps.geometricNormal, 0.0f, [&](int j, size_t q, float cosine) {
        row[j] += weight * dirs.weight[q] * cosine * shape(dirs.x[q], dirs.y[q], dirs.z[q], cosine);
      });
}

}  // namespace acpca
