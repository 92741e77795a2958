// Whole-image copies with streaming stores give the bytes memcpy gives: any 16-byte offset of
// source and destination within a line, sizes ending inside a line, the fallback for unaligned
// copies, and PixelImage's whole copies (which take this path from 1 MB on).
#include "display/stream_copy.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "display/slot_image.h"

namespace frameless {
namespace {

// A 64-byte-aligned window into `v`.
uint8_t* line_start(std::vector<uint8_t>& v) {
  const uintptr_t p = reinterpret_cast<uintptr_t>(v.data());
  return v.data() + ((64 - (p & 63)) & 63);
}

TEST(StreamCopy, CopiesExactlyTheBytesAskedForAtAnyAlignment) {
  std::vector<uint8_t> src_store(8192), dst_store(8192);
  uint8_t* src = line_start(src_store);
  uint8_t* dst = line_start(dst_store);
  for (size_t i = 0; i < 4096 + 128; ++i) src[i] = uint8_t(i * 131u + 7u);
  int cases = 0;
  for (size_t d_off : {0, 16, 32, 48, 3})
    for (size_t s_off : {0, 16, 48, 5})
      for (size_t bytes : {0, 16, 48, 64, 80, 112, 1040, 4096, 77}) {
        std::fill(dst, dst + 4096 + 256, uint8_t(0xAA));
        stream_copy(dst + 64 + d_off, src + s_off, bytes);
        for (size_t i = 0; i < bytes; ++i)
          ASSERT_EQ(dst[64 + d_off + i], src[s_off + i]) << d_off << " " << s_off << " " << bytes << " at " << i;
        for (size_t i = 0; i < 64 + d_off; ++i) ASSERT_EQ(dst[i], 0xAA) << "before, " << bytes;
        for (size_t i = 64 + d_off + bytes; i < 4096 + 256; ++i) ASSERT_EQ(dst[i], 0xAA) << "after, " << bytes;
        ++cases;
      }
  EXPECT_EQ(cases, 5 * 4 * 9);
}

TEST(StreamCopy, WholeImageCopiesArePixelAndRecordExact) {
  PixelImage a, b;
  a.reset(640, 480, nullptr);
  b.reset(640, 480, nullptr);
  for (size_t i = 0; i < a.pixels(); ++i) {
    a.px[i] = {{float(i), 0.5f * float(i), -1.0f}, uint32_t(i * 7u)};
    a.rec[i].last_update = float(i) * 0.25f;
    a.rec[i].count = uint32_t(i);
    a.rec[i].levels = uint8_t(i);
  }
  ASSERT_GE(a.pixels() * sizeof(DisplayPixel), size_t(1) << 20);  // the streaming path
  b.copy_places(a, 0, a.pixels());
  EXPECT_EQ(std::memcmp(a.px.data(), b.px.data(), a.px.size() * sizeof(DisplayPixel)), 0);
  EXPECT_EQ(std::memcmp(a.rec.data(), b.rec.data(), a.rec.size() * sizeof(PlaceRecord)), 0);
}

}  // namespace
}  // namespace frameless
