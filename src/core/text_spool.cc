#include "ocg/core/text_spool.h"

#include <stdexcept>

namespace ocg {

TextSpool::TextSpool() : file_(std::tmpfile()) {}

void TextSpool::Append(const std::string& text) {
  if (file_ && std::fwrite(text.data(), 1, text.size(), file_.get()) != text.size()) {
    // The disk is full: what was written stays readable, the rest goes to memory.
    std::clearerr(file_.get());
    std::string written = Text();
    file_.reset();
    memory_ = std::move(written);
  }
  if (!file_) memory_ += text;
  size_ += text.size();
}

std::string TextSpool::Text() const {
  if (!file_) return memory_;
  std::string text(size_, '\0');
  std::FILE* file = file_.get();
  const long end = std::ftell(file);
  const bool read = std::fflush(file) == 0 && std::fseek(file, 0, SEEK_SET) == 0 &&
                    std::fread(text.data(), 1, size_, file) == size_;
  std::fseek(file, end, SEEK_SET);
  if (!read) throw std::runtime_error("cannot read back a temporary file of the run's log");
  return text;
}

void TextSpool::Clear() {
  file_.reset(std::tmpfile());
  memory_.clear();
  size_ = 0;
}

}  // namespace ocg
