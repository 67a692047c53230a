// zlibCompressForPng: libdeflate behind stb_image_write's STBIW_ZLIB_COMPRESS hook.

#include "clipray/io/FastDeflate.hpp"

#include <libdeflate.h>

#include <cstdlib>
#include <memory>

namespace clipray::detail {

unsigned char* zlibCompressForPng(unsigned char* data, int size, int* outSize, int stbQuality) {
  (void)stbQuality;
  if (data == nullptr || size < 0 || outSize == nullptr) return nullptr;
  // One compressor per thread: images are encoded on worker threads, and a compressor holds
  // state while it works (allocating one costs ~100 KB and a few microseconds, per image).
  struct FreeCompressor {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  thread_local std::unique_ptr<libdeflate_compressor, FreeCompressor> compressor(
      libdeflate_alloc_compressor(kPngDeflateLevel));
  if (!compressor) return nullptr;
  const std::size_t bound = libdeflate_zlib_compress_bound(compressor.get(), std::size_t(size));
  auto* out = static_cast<unsigned char*>(std::malloc(bound));
  if (out == nullptr) return nullptr;
  const std::size_t written =
      libdeflate_zlib_compress(compressor.get(), data, std::size_t(size), out, bound);
  if (written == 0) {
    std::free(out);
    return nullptr;
  }
  *outSize = static_cast<int>(written);
  return out;
}

}  // namespace clipray::detail
