#pragma once
// The page's own files (web/page/: HTML, JavaScript, CSS), built into the
// binary by web/embed_page.cmake.
#include <cstddef>
#include <span>

namespace acpca {

struct PageAsset {
  const char* name;  ///< its path in the site, e.g. "index.html"
  const unsigned char* bytes;
  std::size_t size;
};

/// Every file of the page, in a fixed order.
std::span<const PageAsset> pageAssets();

}  // namespace acpca
