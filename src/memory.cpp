#include "memory.hpp"

#include <unistd.h>
#ifdef __linux__
#include <sys/mman.h>
#endif

#include <cstdint>
#include <cstdio>
#include <initializer_list>

namespace frix {

double memory_available() {
    double bytes = 0.0;
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) bytes = (double)pages * (double)page;
    for (const char *path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"})
        if (std::FILE *f = std::fopen(path, "r")) {
            double limit = 0.0;  // "max" (no limit) does not parse
            if (std::fscanf(f, "%lf", &limit) == 1 && limit > 0.0 && (bytes == 0.0 || limit < bytes)) bytes = limit;
            std::fclose(f);
        }
    return bytes;
}

double resident_memory() {
    double bytes = 0.0;
    const long page = sysconf(_SC_PAGESIZE);
    if (std::FILE *f = std::fopen("/proc/self/statm", "r")) {
        long size = 0, resident = 0;
        if (std::fscanf(f, "%ld %ld", &size, &resident) == 2 && resident > 0 && page > 0)
            bytes = (double)resident * (double)page;
        std::fclose(f);
    }
    return bytes;
}

void advise_huge_pages(void *p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < kHugeArrayBytes) return;
    constexpr uintptr_t kHuge = 2u << 20;
    const uintptr_t begin = ((uintptr_t)p + kHuge - 1) / kHuge * kHuge, end = ((uintptr_t)p + bytes) / kHuge * kHuge;
    // Advice only: where the kernel declines (THP off), the pages stay small.
    if (end > begin) (void)madvise((void *)begin, end - begin, MADV_HUGEPAGE);
#else
    (void)p, (void)bytes;
#endif
}

}  // namespace frix
