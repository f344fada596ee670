#pragma once
// Pictures the viewer and the evaluation report share: 8-bit BGR canvases of
// relit images, cluster boundaries and error heat maps (drawn with OpenCV),
// written as PNG by OpenImageIO as every other image file is.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "imageio/image_output.h"
#include "transport/transport_file.h"

namespace acpca {

/// The image as PNG would store it (SrgbEncoder at the exposure), in BGR order.
cv::Mat toneMappedBgr(const Image& image, double exposureEv);

/// Each pixel's cluster (-1 for background) from each row's cluster.
std::vector<int> clusterOfPixel(const TransportHeader& header,
                                const std::vector<int>& clusterOfRow);

/// Marks pixels whose right or lower neighbour lies in another cluster
/// (background does not count, so silhouettes stay clean).
void drawClusterBoundaries(cv::Mat& bgr, const std::vector<int>& clusterOfPixel,
                           const cv::Vec3b& colour);

/// Per-pixel error |b - truth| (RGB norm) over the truth's RMS pixel norm, on a
/// colour scale from 0 to `scale`; background black.
cv::Mat errorHeatMap(const TransportHeader& header, const std::vector<float>& rowRgb,
                     const std::vector<float>& truthRgb, double scale);

/// Writes an 8-bit BGR canvas as PNG, atomically; throws UserError naming the path.
void writePng(const cv::Mat& bgr, const std::string& path);

}  // namespace acpca
