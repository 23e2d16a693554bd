#include "pkm/text/text_buffer.hpp"

#include <algorithm>

namespace pkm::text {

TextBuffer::TextBuffer(std::size_t capacity_bytes)
    : data_(new char[capacity_bytes]), capacity_(capacity_bytes) {}

void TextBuffer::grow(std::size_t bytes) {
  const std::size_t capacity = std::max(2 * capacity_, size_ + bytes);
  std::unique_ptr<char[]> data(new char[capacity]);
  std::memcpy(data.get(), data_.get(), size_);
  data_ = std::move(data);
  capacity_ = capacity;
}

}  // namespace pkm::text
