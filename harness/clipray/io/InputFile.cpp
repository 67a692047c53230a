#include "clipray/io/InputFile.hpp"

#include <filesystem>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include "clipray/InputError.hpp"

namespace clipray {

namespace {

// Exists, is not a directory, and is a regular file (a FIFO with no writer blocks forever).
void requireRegularFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);  // follows symbolic links
  if (error || !fs::exists(status)) throw InputError(path + ": cannot open file");
  if (fs::is_directory(status)) throw InputError(path + ": is a directory, not a file");
  if (!fs::is_regular_file(status)) {
    throw InputError(path + ": is not a regular file (a FIFO, device or socket)");
  }
}

}  // namespace

void requireReadableFile(const std::string& path) {
  requireRegularFile(path);
  if (access(path.c_str(), R_OK) != 0) throw InputError(path + ": cannot read file");
}

std::string readInputFile(const std::string& path, std::uint64_t maxBytes, std::string_view what) {
  requireRegularFile(path);
  namespace fs = std::filesystem;
  std::error_code error;
  const std::uintmax_t size = fs::file_size(path, error);
  if (error) throw InputError(path + ": cannot read file");
  if (size > maxBytes) {
    throw InputError(path + ": " + std::to_string(size) + " bytes, more than the " +
                     std::to_string(maxBytes) + " a " + std::string(what) + " may have");
  }
  std::ifstream stream(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!stream || !stream.read(bytes.data(), static_cast<std::streamsize>(size))) {
    throw InputError(path + ": cannot read file");
  }
  return bytes;
}

void requireNoNulBytes(std::string_view text, const std::string& path) {
  const std::size_t nul = text.find('\0');
  if (nul != std::string_view::npos) {
    throw InputError(path + ": byte " + std::to_string(nul) + ": a NUL byte in a text file");
  }
}

}  // namespace clipray
