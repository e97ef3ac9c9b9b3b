// libFuzzer target: the STL reader on arbitrary bytes, then format detection (see fuzz_reader.h).

#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  st::fuzz::read_as(data, size, st::MeshFormat::Stl, "fuzz.stl");
  st::fuzz::read_as(data, size, st::MeshFormat::Auto, "fuzz.stl");
  return 0;
}
