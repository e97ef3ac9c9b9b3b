// libFuzzer target: the OBJ reader on arbitrary bytes, then format detection (see fuzz_reader.h).

#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  st::fuzz::read_as(data, size, st::MeshFormat::Obj, "fuzz.obj");
  st::fuzz::read_as(data, size, st::MeshFormat::Auto, "fuzz.obj");
  return 0;
}
