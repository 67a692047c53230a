#pragma once
// The zlib stream of a PNG's IDAT, compressed by libdeflate instead of stb_image_write's own
// deflate (plugged in through STBIW_ZLIB_COMPRESS in Images.cpp). stb's encoder is simple and
// single-pass: on a 1080p suite it was 54% of the whole process's CPU. libdeflate at a low level
// writes a slightly smaller stream several times faster; stb_image_write stays the PNG writer
// (filters, chunks, CRCs).

namespace clipray::detail {

// STBIW_ZLIB_COMPRESS's contract: a zlib stream of data[0, size) in memory from malloc() (stb
// frees it with free()), its length in *outSize; nullptr on failure. stbQuality (stb's
// compression level, 8 by default) is not used: the level is kPngDeflateLevel.
unsigned char* zlibCompressForPng(unsigned char* data, int size, int* outSize, int stbQuality);

// libdeflate's level for PNGs: 1, its fastest. The reconcile's images are large flat areas and
// smooth ramps; on standard.json at 1920x1080 (8 PNGs) level 1 wrote 219 KB where stb's own
// deflate wrote 631 KB.
inline constexpr int kPngDeflateLevel = 1;

}  // namespace clipray::detail
