#pragma once
// Albedo textures: linear RGB images looked up bilinearly at a surface's
// texture coordinates. 8- and 16-bit files are sRGB-encoded (as glTF requires
// and as OBJ/Collada textures are painted) and decoded to linear on load;
// float files (EXR, HDR) are linear already.
#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/srgb.h"

namespace acpca {

class Texture {
 public:
  /// rgb: width x height linear values, row 0 at the top of the image.
  Texture(std::string name, int width, int height, std::vector<float> rgb);

  const std::string& name() const { return name_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// The texel at column x, row y (row 0 at the top).
  Eigen::Vector3f texel(int x, int y) const;
  /// Bilinear lookup between texel centres with repeat wrapping. uv as assimp
  /// gives it for every format: u to the right, v up, (0, 0) the image's
  /// bottom-left corner.
  Eigen::Vector3f sample(const Eigen::Vector2f& uv) const;

 private:
  std::string name_;
  int width_, height_;
  std::vector<float> rgb_;
};

/// Reads a texture with OpenImageIO (PNG, JPEG, TGA, EXR, ...). Grey images
/// give grey albedo; alpha is ignored. Throws UserError naming the file for a
/// missing, unreadable or non-finite image; negative float texels are clamped
/// to 0 with a warning.
std::shared_ptr<const Texture> loadTexture(const std::string& path);
/// The same from an image file's bytes in memory (a texture embedded in a glTF
/// or FBX file); formatHint is its extension ("png", "jpg").
std::shared_ptr<const Texture> loadTextureFromMemory(const std::string& name,
                                                     const std::string& formatHint,
                                                     const void* bytes, size_t size);

}  // namespace acpca
