// Invariant checks inside fuzz targets: a failed check is a finding like a crash (libFuzzer saves
// the input on abort), so round trips and other properties are tested on every accepted input.
#pragma once
#include <cstdio>
#include <cstdlib>

#define LGN_FUZZ_CHECK(cond, what)                                                                      \
  do {                                                                                                  \
    if (!(cond)) {                                                                                      \
      std::fprintf(stderr, "%s:%d: fuzz invariant failed: %s (%s)\n", __FILE__, __LINE__, #cond, what); \
      std::abort();                                                                                     \
    }                                                                                                   \
  } while (0)
