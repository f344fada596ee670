#pragma once
// An Embree device as the precompute and the relighter's shadow rays both
// make it: quiet, with Embree's errors reported as warnings in its own words
// before the caller's check of rtcGetDeviceError turns them into a failure.
#include <embree3/rtcore.h>

namespace acpca {

/// Never null: a device that cannot be made is an internal error naming
/// Embree's code. The caller releases it (rtcReleaseDevice).
RTCDevice newEmbreeDevice();

}  // namespace acpca
