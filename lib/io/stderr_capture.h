#pragma once
// Standard error (file descriptor 2) sent to a temporary file for a while, for what other code
// prints there and vrv must say in its own one line instead: libpng's second error line inside
// OpenImageIO (image_module_oiio.cpp), a plot script's traceback (vrv verify's plot).  Child
// processes started meanwhile inherit it.  Header-only: the image module, a shared object of its
// own, uses it too.  Captures hold a mutex, so two never swap descriptor 2 at once; another
// thread's stderr during a capture is caught with it (vrv captures while nothing else prints).
#include <unistd.h>

#include <cstdio>
#include <mutex>
#include <string>

namespace vrv {

class StderrCapture {
 public:
  StderrCapture() : lock_(mutex()) {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = file_ ? ::dup(2) : -1;
    if (saved_ < 0 || ::dup2(::fileno(file_), 2) < 0) restore();  // then nothing is captured
  }
  ~StderrCapture() { restore(); }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Ends the capture; what was written meanwhile.
  std::string release() {
    std::fflush(stderr);
    std::string text;
    if (file_ && saved_ >= 0) {
      std::rewind(file_);
      char buf[4096];
      for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, file_)) > 0;) text.append(buf, n);
    }
    restore();
    return text;
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  void restore() {
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
      saved_ = -1;
    }
    if (file_) std::fclose(file_);
    file_ = nullptr;
  }
  std::lock_guard<std::mutex> lock_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// The last non-empty line of `text` (a traceback's exception line), without its line break.
inline std::string last_line(const std::string& text) {
  std::size_t end = text.find_last_not_of("\r\n ");
  if (end == std::string::npos) return {};
  const std::size_t begin = text.rfind('\n', end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1, end + 1 - (begin == std::string::npos ? 0 : begin + 1));
}

}  // namespace vrv
