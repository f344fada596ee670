#pragma once
// The paper's dimensionality analysis ([Mahajan07] sec. 3, Fig. 5/7): how many
// eigenvectors a square patch of the image needs as the patch grows, and the
// power law n ~ A^s fitted to it, from which mu = r^-s (sec. 5.1) and the
// optimal patch size p* (eq. 27) follow.
#include <vector>

#include "transport/transport_file.h"

namespace acpca {

/// Rows of T for the occupied pixels of the side x side square centred on
/// (cx, cy), clipped to the image: rows x l, row-major.
struct PatchRows {
  long long rows = 0;
  std::vector<float> values;
};
PatchRows readSquarePatch(const TransportReader& transport, int cx, int cy, int side);

/// Eigenvalues needed to hold `energy` of the rows' energy (from the smaller Gram
/// matrix, rows x rows or l x l). 0 for no rows or no energy.
int patchDimensionality(const PatchRows& patch, int latticeSize, double energy);

/// Least squares fit of log y = slope log x + log scale over the points with
/// x, y > 0 (natural logs); slope NAN with fewer than two distinct x.
struct PowerLaw {
  double slope = 0, scale = 0;
  int points = 0;
};
PowerLaw fitPowerLaw(const std::vector<double>& x, const std::vector<double>& y);

/// mu = r^-slope (sec. 5.1): the share of a patch's bases each of its r parts needs.
double muFromSlope(double slope, int r);

}  // namespace acpca
