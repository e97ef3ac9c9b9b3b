#pragma once
// gzip decompression for compressed mesh files (*.stl.gz and the like).

#include <cstddef>
#include <string>
#include <vector>

namespace st::detail {

/// True when the bytes start with the gzip magic number.
bool is_gzip(const char* data, std::size_t size);

/// Inflates a whole gzip stream (possibly several members). Throws InvalidInput naming `name` when
/// the data is corrupt or truncated, or would inflate beyond `max_size` bytes. The default limit is
/// deflate's largest possible ratio (1032:1) times the input plus 1 MiB, capped at 4 GiB, so a small
/// hostile file cannot make the reader allocate gigabytes.
std::vector<char> gunzip(const char* data, std::size_t size, const std::string& name, std::size_t max_size = 0);

/// The first bytes (at most `max_size`) that the start of a gzip stream inflates to: `data` may stop
/// anywhere (e.g. the first 64 KiB of a file). Throws InvalidInput naming `name` for corrupt data.
std::vector<char> gunzip_prefix(const char* data, std::size_t size, const std::string& name, std::size_t max_size);

} // namespace st::detail
