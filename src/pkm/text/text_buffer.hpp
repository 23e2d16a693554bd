// A growing run of text written in place: the text outputs build lines in one of these and hand
// it to a file when it fills. Room at its end is made without being initialised, so that a
// number is written straight into it (decimal_text.hpp) and the buffer, once grown, never
// allocates again.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <string_view>

namespace pkm::text {

class TextBuffer {
 public:
  explicit TextBuffer(std::size_t capacity_bytes = 4096);

  // At least `bytes` writable from the returned pointer, uninitialised; then commit(end) with
  // the end of what was written.
  char* room(std::size_t bytes) {
    if (capacity_ - size_ < bytes) grow(bytes);
    return data_.get() + size_;
  }
  void commit(const char* end) { size_ = static_cast<std::size_t>(end - data_.get()); }

  void append(std::string_view text) {
    std::memcpy(room(text.size()), text.data(), text.size());
    size_ += text.size();
  }
  void push_back(char c) {
    *room(1) = c;
    ++size_;
  }
  void append(std::size_t count, char c) {
    std::memset(room(count), c, count);
    size_ += count;
  }

  std::string_view view() const { return {data_.get(), size_}; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void clear() { size_ = 0; }

 private:
  void grow(std::size_t bytes);
  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace pkm::text
