// The query points of a batch as the engine reads them.
#pragma once

#include <cstdint>

namespace invmap::engine {

/// Query points as structure of arrays, already in double precision.
struct QueryPoints {
  std::int64_t count = 0;
  const double* coord[3] = {nullptr, nullptr, nullptr};  ///< coord[2] null in 2D.
};

}  // namespace invmap::engine
