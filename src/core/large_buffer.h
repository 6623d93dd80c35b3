// Whole-image buffers backed by 2 MB pages where the kernel allows it.
//
// Why: every fresh 4 KB page of a buffer costs a page fault when it is first written — about 0.2 µs
// on bare metal, 15–30 µs on a virtual machine that traps each one — and a 2048² RGB float image is
// 12 800 pages. Linux's transparent huge pages in "madvise" mode (Debian's default) back a region
// with 2 MB pages once it is advised, which turns those faults into a few dozen: reading and
// converting a 2048² plain lightmap on the project's VM took 40 % less time (docs/performance.md
// "Whole conversions"). Contents and sizes are those of std::vector::assign; only the kernel's paging
// differs, so no output byte depends on it.
#pragma once
#include <cstddef>
#include <vector>

namespace ahd {

// Advises the kernel to back the 2 MB-aligned part of [p, p + bytes) with huge pages. A no-op below
// 4 MB, off Linux, or where the kernel refuses (THP "never"); never fails. Call it before the
// memory is first written: pages already faulted in stay as they are.
void advise_huge_pages(void* p, size_t bytes);

// v.assign(n, value), with the new storage advised for huge pages before it is filled. Reuses v's
// storage when it is large enough. Throws std::bad_alloc as std::vector does.
template <class T>
void assign_large(std::vector<T>& v, size_t n, const T& value) {
  if (v.capacity() < n) {
    std::vector<T>().swap(v);
    v.reserve(n);
  }
  advise_huge_pages(v.data(), n * sizeof(T));
  v.assign(n, value);
}

}  // namespace ahd
