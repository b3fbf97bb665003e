// A check of a classic netCDF file's header (the format of most Exodus II
// files) before the netCDF library opens it: the library allocates what the
// header claims (an attribute of 3 GB in a 1 kB file) before noticing that
// the file cannot hold it.
#pragma once

#include <string>

namespace invmap::fem {

/// Walks the header of the classic netCDF file at `path` (CDF-1, CDF-2 or
/// CDF-5; netCDF-4's HDF5 files pass unchecked), reading at most its first
/// 64 MiB, and returns what is wrong when a count or a length it declares
/// does not fit in them, when a variable's values reach past the file's end
/// (a file cut short, whose missing values the library would read as
/// zeros), or the file starts with neither signature, else an empty string.
std::string CheckNetcdfHeader(const std::string& path);

}  // namespace invmap::fem
