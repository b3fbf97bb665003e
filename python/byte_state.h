// Byte strings of trivially copyable values and vectors, the pickled state
// of manifolds (geometry_state.cpp, fields_binding.cpp): values in native
// byte order, vectors as a 64-bit length and their elements.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace invmap::python {

/// Appends values and vectors to a byte string.
class StateWriter {
 public:
  explicit StateWriter(std::string* out) : out_(out) {}

  template <typename T>
  void Value(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_->append(reinterpret_cast<const char*>(&value), sizeof(T));
  }

  /// The length as a uint64, then the elements.
  template <typename T>
  void Vector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    Value<std::uint64_t>(values.size());
    out_->append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }

 private:
  std::string* out_;
};

/// Reads what StateWriter wrote, checking every length against the bytes
/// left; a short buffer throws std::invalid_argument "<what>: truncated".
class StateReader {
 public:
  StateReader(const char* data, std::size_t size, std::string what) : data_(data), left_(size), what_(std::move(what)) {}

  template <typename T>
  T Value() {
    T value;
    Take(&value, sizeof(T));
    return value;
  }

  template <typename T>
  std::vector<T> Vector() {
    const std::uint64_t count = Value<std::uint64_t>();
    // Dividing (not multiplying) so that a corrupt length cannot overflow.
    if (count > left_ / sizeof(T)) throw std::invalid_argument(what_ + ": truncated");
    std::vector<T> values(static_cast<std::size_t>(count));
    Take(values.data(), values.size() * sizeof(T));
    return values;
  }

  bool AtEnd() const { return left_ == 0; }

 private:
  void Take(void* out, std::size_t bytes) {
    if (bytes > left_) throw std::invalid_argument(what_ + ": truncated");
    if (bytes) std::memcpy(out, data_, bytes);
    data_ += bytes;
    left_ -= bytes;
  }

  const char* data_;
  std::size_t left_;
  std::string what_;
};

}  // namespace invmap::python
