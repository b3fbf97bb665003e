// Why a STEP or IGES file gave OpenCascade's reader no shape, where its
// text tells: it is not of the format at all (its first record is not the
// format's header), or it is cut short (it lacks the format's closing
// record). The readers themselves answer both with a bare failure or with
// no shape.
#pragma once

#include <string>

namespace invmap::cad {

/// "not an IGES file (...)" or "a truncated IGES file (...)", likewise for
/// STEP (`format` "STEP" or "IGES"); empty when the file has its format's
/// first and last records.
std::string DescribeBrokenExchangeFile(const std::string& path, const std::string& format);

}  // namespace invmap::cad
