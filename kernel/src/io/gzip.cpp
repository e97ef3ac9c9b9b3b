#include "detail/gzip.h"

#include "st/core/errors.h"

#include <zlib.h>

#include <algorithm>
#include <climits>

namespace st::detail {

bool is_gzip(const char* data, std::size_t size) {
  return size >= 2 && static_cast<unsigned char>(data[0]) == 0x1f && static_cast<unsigned char>(data[1]) == 0x8b;
}

namespace {

/// Inflates into at most max_size bytes; `prefix`: stops there, and at the end of the data, without
/// an error.
std::vector<char> inflate_gzip(const char* data, std::size_t size, const std::string& name, std::size_t max_size,
                               bool prefix) {
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw InvalidInput(name + ": cannot start gzip decompression");
  std::vector<char> out(std::min(max_size, std::max<std::size_t>(size * 3, 1 << 16)));
  std::size_t produced = 0;
  std::size_t consumed = 0;
  int rc = Z_OK;
  while (true) {
    if (produced == out.size()) {
      if (out.size() >= max_size) {
        inflateEnd(&z);
        if (prefix) return out;
        throw InvalidInput(name + ": gzip data inflates beyond " + std::to_string(max_size >> 20) + " MB");
      }
      out.resize(std::min(out.size() * 2, max_size));
    }
    const std::size_t in_chunk = std::min<std::size_t>(size - consumed, UINT_MAX);
    const std::size_t out_chunk = std::min<std::size_t>(out.size() - produced, UINT_MAX);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data + consumed));
    z.avail_in = static_cast<uInt>(in_chunk);
    z.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    z.avail_out = static_cast<uInt>(out_chunk);
    rc = inflate(&z, Z_NO_FLUSH);
    consumed += in_chunk - z.avail_in;
    produced += out_chunk - z.avail_out;
    if (rc == Z_STREAM_END) {
      if (consumed < size && is_gzip(data + consumed, size - consumed)) {
        inflateReset(&z); // another gzip member follows
        continue;
      }
      break;
    }
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      inflateEnd(&z);
      throw InvalidInput(name + ": corrupt gzip data (" + std::string(z.msg ? z.msg : "inflate failed") + ")");
    }
    if (rc == Z_BUF_ERROR && consumed == size && produced < out.size()) {
      if (prefix) break;
      inflateEnd(&z);
      throw InvalidInput(name + ": truncated gzip data");
    }
  }
  inflateEnd(&z);
  out.resize(produced);
  return out;
}

} // namespace

std::vector<char> gunzip(const char* data, std::size_t size, const std::string& name, std::size_t max_size) {
  if (max_size == 0) max_size = std::min<std::size_t>(std::size_t{4} << 30, 1032 * size + (std::size_t{1} << 20));
  return inflate_gzip(data, size, name, max_size, false);
}

std::vector<char> gunzip_prefix(const char* data, std::size_t size, const std::string& name, std::size_t max_size) {
  return inflate_gzip(data, size, name, max_size, true);
}

} // namespace st::detail
