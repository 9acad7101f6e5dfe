#pragma once
// Text that only grows for the whole run and is read back once at its end (a log kept as
// an output, e.g. ocg_observations.jsonl), kept in an unnamed temporary file rather than
// in memory, so a long run does not grow by it (issue 33: about 0.2 kB a frame). Falls
// back to memory when no temporary file can be made.
//
// Not thread-safe; not copyable.

#include <cstdio>
#include <memory>
#include <string>

namespace ocg {

class TextSpool {
 public:
  TextSpool();
  TextSpool(const TextSpool&) = delete;
  TextSpool& operator=(const TextSpool&) = delete;

  void Append(const std::string& text);
  // Everything appended since the last Clear(). Throws std::runtime_error when the
  // temporary file cannot be read back.
  std::string Text() const;
  void Clear();
  std::size_t size() const { return size_; }  // bytes
  bool empty() const { return size_ == 0; }

 private:
  struct Closer {
    void operator()(std::FILE* file) const { std::fclose(file); }
  };
  std::unique_ptr<std::FILE, Closer> file_;
  std::string memory_;  // without a file
  std::size_t size_ = 0;
};

}  // namespace ocg
