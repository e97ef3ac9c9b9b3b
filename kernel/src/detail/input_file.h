#pragma once
// The check every file reader makes before it opens a file: it exists, it is a regular file (not a
// directory, a device such as /dev/zero or a FIFO, which would be read forever or block), and it is
// not over the reader's size limit (st/tolerances.h).

#include "st/core/errors.h"
#include "st/core/tolerances.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace st::detail {

/// The file's size in bytes. Throws InvalidInput "<path>: cannot open the <what>: ..." naming why.
inline std::uintmax_t check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  const std::string prefix = path + ": cannot open the " + what + ": ";
  if (ec || !fs::exists(status))
    throw InvalidInput(prefix + (ec ? ec.message() : std::string("No such file or directory")));
  if (fs::is_directory(status)) throw InvalidInput(prefix + "it is a directory");
  if (!fs::is_regular_file(status)) {
    const char* kind = fs::is_fifo(status)             ? "a FIFO (named pipe)"
                       : fs::is_character_file(status) ? "a character device"
                       : fs::is_block_file(status)     ? "a block device"
                       : fs::is_socket(status)         ? "a socket"
                                                       : "not a regular file";
    throw InvalidInput(prefix + "it is " + kind + ", not a regular file");
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw InvalidInput(prefix + ec.message());
  if (size > max_bytes)
    throw InvalidInput(prefix + "it has " + std::to_string(size) + " bytes, over the limit of " +
                       std::to_string(max_bytes >> 20) + " MiB");
  return size;
}

/// The first `bytes` bytes of a file (all of a shorter one), checked as above.
inline std::string read_file_start(const std::string& path, const std::string& what, std::size_t bytes) {
  check_input_file(path, what, tol::kMaxMeshFileBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput(path + ": cannot open the " + what);
  std::string out(bytes, '\0');
  in.read(out.data(), static_cast<std::streamsize>(bytes));
  out.resize(static_cast<std::size_t>(in.gcount()));
  return out;
}

/// Writes `text` to `path` through a temporary file renamed over it, so a reader never sees half a
/// file and a failure leaves no file behind. InvalidInput naming the path and the reason.
inline void write_text_atomically(const std::string& path, const std::string& text, const std::string& what) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InvalidInput(path + ": cannot write the " + what);
    out << text;
    out.close();
    if (!out) {
      std::filesystem::remove(tmp);
      throw InvalidInput(path + ": cannot write the " + what);
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw InvalidInput(path + ": cannot write the " + what + ": " + ec.message());
  }
}

} // namespace st::detail
