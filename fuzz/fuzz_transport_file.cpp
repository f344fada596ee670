// Raw bytes as a transport file: refused with a UserError, or opened and its
// first rows read back finite.
#include "fuzz/fuzz_support.h"
#include "transport/transport_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  const std::string path = fuzz::writeInput(data, size, ".h5");
  return fuzz::runReader([&] {
    const TransportReader reader(path);
    const long long rows = std::min<long long>(reader.rows(), 8);
    std::vector<float> values(static_cast<size_t>(rows) * reader.rowLength());
    reader.readRows(0, rows, values.data());
    fuzz::requireFinite(values, "transport value");
  });
}
