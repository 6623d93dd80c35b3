// core/large_buffer.h: the huge-page advice changes only how the kernel pages the storage, never
// what std::vector::assign would hold.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/large_buffer.h"

namespace ahd {

TEST(LargeBuffer, AssignLargeHoldsWhatAssignHolds) {
  for (size_t n : {size_t(0), size_t(1), size_t(1000), size_t(3) << 20}) {  // below and above the 4 MB threshold
    std::vector<float> v = {7.0f, 8.0f};
    assign_large(v, n, 0.5f);
    ASSERT_EQ(v.size(), n);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(v[i], 0.5f) << n << " " << i;
  }
  // Storage large enough is reused (a level's buffer is not reallocated for the same size).
  std::vector<uint8_t> b;
  assign_large(b, size_t(8) << 20, uint8_t(1));
  const uint8_t* p = b.data();
  assign_large(b, size_t(5) << 20, uint8_t(2));
  EXPECT_EQ(b.data(), p);
  EXPECT_EQ(b.size(), size_t(5) << 20);
  EXPECT_EQ(b.front(), 2);
  EXPECT_EQ(b.back(), 2);
  // The images built on it are zeroed.
  const ImageF img(1500, 1000, 3);  // 18 MB: advised
  for (float x : img.data) ASSERT_EQ(x, 0.0f);
  EXPECT_EQ(img.data.size(), size_t(1500) * 1000 * 3);
}

TEST(LargeBuffer, AdviceNeverFailsOnAnyRange) {
  std::vector<uint8_t> v(size_t(9) << 20, 3);
  advise_huge_pages(nullptr, 0);
  advise_huge_pages(v.data() + 1, v.size() - 3);  // unaligned ends: only the aligned inside is advised
  advise_huge_pages(v.data(), 100);
  for (uint8_t x : v) ASSERT_EQ(x, 3);  // advice on memory in use keeps its contents
}

}  // namespace ahd
