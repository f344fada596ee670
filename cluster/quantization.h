#pragma once
// Storing a model's values in fewer bits: coefficients as f16 or i8 (one scale
// per cluster basis), bases and means rounded to half.
#include <vector>

#include "model/model.h"

namespace acpca {

/// Stores a model's f32 coefficients as `precision` (f16, or i8 with one scale
/// per cluster basis: the largest |value| of that basis's coefficients / 127,
/// so a basis of small coefficients keeps its own fine step); returns the squared error this adds
/// to the transport (orthonormal bases: the coefficients' squared error).
double storeCoefficients(Model& model, CoeffPrecision precision);

/// Rounds every value to the nearest half (kept as float).
void roundToHalf(std::vector<float>& values);

}  // namespace acpca
