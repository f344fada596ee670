#include "lighting/map_source_listing.h"

#include <numbers>

#include "lighting/sh_lighting.h"

namespace acpca {

std::vector<MapSource> turnedSources(const std::vector<MapSource>& sources,
                                     const EnvRotation& rotation) {
  const Eigen::Matrix3d turn = rotationMatrix(rotation);
  std::vector<MapSource> turned;
  for (const MapSource& s : sources) turned.push_back(s.turned(turn));
  return turned;
}

nlohmann::json sourcesJson(const std::vector<MapSource>& sources) {
  nlohmann::json list = nlohmann::json::array();
  for (const MapSource& s : sources)
    list.push_back({{"direction", {s.direction[0], s.direction[1], s.direction[2]}},
                    {"theta_deg", s.thetaDegrees()},
                    {"phi_deg", s.phiDegrees()},
                    {"radius_deg", s.radius * (180 / std::numbers::pi)},
                    {"radiance", {s.radiance[0], s.radiance[1], s.radiance[2]}},
                    {"energy_share", s.energyShare}});
  return list;
}

nlohmann::json sh9Json(const std::array<Rgb, 9>& lattice, const std::vector<MapSource>& sources) {
  std::array<Rgb, 9> sum = lattice;
  for (const MapSource& s : sources) {
    const std::array<Rgb, 9> disc = projectDisc(s);
    for (int k = 0; k < 9; ++k) sum[k] += disc[k];
  }
  nlohmann::json list = nlohmann::json::array();
  for (const Rgb& c : sum) list.push_back({c.x(), c.y(), c.z()});
  return list;
}

}  // namespace acpca
