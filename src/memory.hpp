// What the process may use and what it holds, from the operating system: the ground of the
// memory checks (the Monitor's memory_left, the reduction's fit).
#pragma once

#include <cstddef>
#include <vector>

namespace frix {

// The memory this process may use: the machine's, or its control group's limit where lower
// (a container). 0 when unknown.
double memory_available();

// The process's resident memory now (Linux: /proc/self/statm). 0 when unknown.
double resident_memory();

// Asks the kernel to back the 2 MiB-aligned pages of [p, p + bytes) with transparent huge
// pages (Linux, where THP is "always" or "madvise"; elsewhere nothing), for an array of at
// least kHugeArrayBytes not yet touched: its first touch then costs one fault a 2 MiB page
// instead of one a 4 kiB page, which on some virtual machines is most of a large setup's time.
constexpr size_t kHugeArrayBytes = 4u << 20;
void advise_huge_pages(void *p, size_t bytes);

// v (its values may be dropped) with room for n elements: storage it has, or new storage
// advised as above before its first touch.
template <class T, class A>
void reserve_advised(std::vector<T, A> &v, size_t n) {
    if (v.capacity() >= n) return;
    std::vector<T, A>().swap(v);
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
}

// v holding n copies of value, in storage as reserve_advised gives.
template <class T, class A>
void assign_advised(std::vector<T, A> &v, size_t n, const T &value = T()) {
    reserve_advised(v, n);
    v.assign(n, value);
}

// v holding a copy of the n values at first, in storage as reserve_advised gives.
template <class T, class A>
void copy_advised(std::vector<T, A> &v, const T *first, size_t n) {
    reserve_advised(v, n);
    v.assign(first, first + n);
}

}  // namespace frix
