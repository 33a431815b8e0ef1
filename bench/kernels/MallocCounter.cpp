#include "MallocCounter.hpp"

#include <cstddef>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
}

namespace {
std::size_t count = 0;
}

std::size_t bench::allocations() { return count; }

extern "C" {
void* malloc(std::size_t n) {
  ++count;
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t s) {
  ++count;
  return __libc_calloc(n, s);
}
void* realloc(void* p, std::size_t n) {
  ++count;
  return __libc_realloc(p, n);
}
void free(void* p) { __libc_free(p); }
}
