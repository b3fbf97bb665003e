// INVMAP_API marks what the shared library libinvmap exports. The library is
// compiled with hidden symbols, so everything declared in include/invmap/
// that the library defines (a free function, or a class or struct with
// member functions that are not inline) carries INVMAP_API, or a program
// cannot link to it.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define INVMAP_API __attribute__((visibility("default")))
#else
#define INVMAP_API
#endif
