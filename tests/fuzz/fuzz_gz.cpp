// libFuzzer target: gzip inflation of arbitrary bytes, then the inflated data read as a mesh (format
// detected). st::InvalidInput is the only allowed way to refuse an input.

#include "detail/gzip.h"
#include "st/core/errors.h"
#include "st/io/mesh_io.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const char* bytes = reinterpret_cast<const char*>(data);
    if (!st::detail::is_gzip(bytes, size)) return 0;
    const std::vector<char> plain = st::detail::gunzip(bytes, size, "fuzz.stl.gz");
    st::read_mesh_from_memory(plain.data(), plain.size(), st::MeshFormat::Auto, "fuzz.stl.gz");
  } catch (const st::InvalidInput&) {
    // A refused input: fine.
  }
  return 0;
}
