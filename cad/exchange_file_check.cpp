#include "cad/exchange_file_check.h"

#include <algorithm>
#include <fstream>

namespace invmap::cad {
namespace {

/// An IGES record: 80 columns, its section letter in column 73 (S start,
/// G global, D directory, P parameter, T terminate).
char IgesSection(std::string line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  return line.size() >= 73 ? line[72] : '\0';
}

std::string DescribeIges(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, last;
  std::size_t lines = 0, lastAt = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++lines;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (first) {
      const char section = IgesSection(line);
      if (section != 'S' && section != 'G') {
        return "not an IGES file (its first line is not an IGES Start or Global record: no 'S' or 'G' in column 73)";
      }
      first = false;
    }
    last = line;
    lastAt = lines;
  }
  if (first) return "not an IGES file (no records)";
  if (IgesSection(last) != 'T') {
    return "a truncated IGES file (it ends at line " + std::to_string(lastAt) +
           " without the Terminate record, 'T' in column 73)";
  }
  return "";
}

std::string DescribeStep(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(256, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::size_t start = head.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || head.compare(start, 13, "ISO-10303-21;") != 0) {
    return "not a STEP file (it does not begin with ISO-10303-21;)";
  }
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff tailSize = std::min<std::streamoff>(size, 256);
  std::string tail(static_cast<std::size_t>(tailSize), '\0');
  in.seekg(size - tailSize);
  in.read(&tail[0], tailSize);
  if (tail.find("END-ISO-10303-21;") == std::string::npos) {
    return "a truncated STEP file (it ends without END-ISO-10303-21;)";
  }
  return "";
}

}  // namespace

std::string DescribeBrokenExchangeFile(const std::string& path, const std::string& format) {
  return format == "IGES" ? DescribeIges(path) : DescribeStep(path);
}

}  // namespace invmap::cad
