// Two kinds of checks.
//  INVMAP_VERIFY(cond, msg): validates user input once per batch; always on;
//    throws std::invalid_argument, which the API boundary turns into an error.
//  INVMAP_ASSERT(cond, msg): internal invariants and index ranges; compiled
//    out unless the build sets INVMAP_ASSERT=ON; aborts with the message.
// Messages are stream expressions: INVMAP_ASSERT(i < n, "cell " << i << " of " << n).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#define INVMAP_VERIFY(cond, msg)                     \
  do {                                               \
    if (!(cond)) {                                   \
      std::ostringstream invmapVerifyMessage;        \
      invmapVerifyMessage << msg;                    \
      throw std::invalid_argument(invmapVerifyMessage.str()); \
    }                                                \
  } while (false)

#if INVMAP_ENABLE_ASSERT
#define INVMAP_ASSERT(cond, msg)                                                                     \
  do {                                                                                               \
    if (!(cond)) {                                                                                   \
      std::ostringstream invmapAssertMessage;                                                        \
      invmapAssertMessage << msg;                                                                    \
      std::fprintf(stderr, "%s:%d: assertion %s failed: %s\n", __FILE__, __LINE__, #cond,            \
                   invmapAssertMessage.str().c_str());                                               \
      std::abort();                                                                                  \
    }                                                                                                \
  } while (false)
#else
#define INVMAP_ASSERT(cond, msg) \
  do {                           \
  } while (false)
#endif
