#pragma once
// gzip decompression for compressed mesh files (*.stl.gz and the like).

#include <cstddef>
#include <string>
#include <vector>

namespace st::detail {

/// True when the bytes start with the gzip magic number.
bool is_gzip(const char* data, std::size_t size);

/// Inflates a whole gzip stream (possibly several members). Throws InvalidInput naming `name` when
/// the data is corrupt or truncated, or would inflate beyond `max_size` bytes.
std::vector<char> gunzip(const char* data, std::size_t size, const std::string& name,
                         std::size_t max_size = std::size_t{8} << 30);

} // namespace st::detail
