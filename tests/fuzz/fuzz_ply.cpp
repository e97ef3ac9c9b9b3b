// libFuzzer target: the PLY reader on arbitrary bytes, then format detection (see fuzz_reader.h).

#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  st::fuzz::read_as(data, size, st::MeshFormat::Ply, "fuzz.ply");
  st::fuzz::read_as(data, size, st::MeshFormat::Auto, "fuzz.ply");
  return 0;
}
