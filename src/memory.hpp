// What the process may use and what it holds, from the operating system: the ground of the
// memory checks (the Monitor's memory_left, the reduction's fit).
#pragma once

namespace frix {

// The memory this process may use: the machine's, or its control group's limit where lower
// (a container). 0 when unknown.
double memory_available();

// The process's resident memory now (Linux: /proc/self/statm). 0 when unknown.
double resident_memory();

}  // namespace frix
