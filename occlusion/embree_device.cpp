#include "occlusion/embree_device.h"

#include "core/error.h"
#include "core/warning.h"

namespace acpca {

namespace {

void onEmbreeError(void*, RTCError code, const char* message) {
  warn(concat("Embree error ", static_cast<int>(code), ": ", message ? message : ""));
}

}  // namespace

RTCDevice newEmbreeDevice() {
  RTCDevice device = rtcNewDevice("verbose=0");
  ACPCA_CHECK(device != nullptr, "rtcNewDevice failed (error ",
              static_cast<int>(rtcGetDeviceError(nullptr)), ")");
  rtcSetDeviceErrorFunction(device, onEmbreeError, nullptr);
  return device;
}

}  // namespace acpca
