// app/line_reader.hpp -- a fast line reader over a FILE*, for the CLI's stdin formats.
//
// Contract: next() hands out one physical line at a time as a view into an internal buffer
// (valid until the next call), without the '\n' and without one trailing '\r' (CRLF input).
// A last line without a newline is still a line. Lines may be of any length (the buffer grows).
// Reads with read(2) when the stream has a file descriptor, so input arriving through a pipe or
// a terminal is processed as it comes; the before_read hook runs before every call that may
// block, which is where the caller flushes its output. Falls back to fread() for streams
// without a descriptor (fmemopen in tests).
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string_view>
#include <vector>

namespace tetia::app {

class LineReader {
 public:
  explicit LineReader(std::FILE* in, std::size_t chunk = std::size_t{1} << 20)
      : in_(in), fd_(in ? ::fileno(in) : -1), buf_(chunk < 16 ? 16 : chunk) {}

  /// Called before every read that may block (e.g. to flush pending output).
  void set_before_read(std::function<void()> hook) { before_read_ = std::move(hook); }

  /// The next line, or false at the end of the input (or on a read error: see failed()).
  bool next(std::string_view& line) {
    for (;;) {
      if (pos_ < end_) {
        const char* b = buf_.data() + pos_;
        if (const void* nl = std::memchr(b, '\n', end_ - pos_)) {
          const auto len = static_cast<std::size_t>(static_cast<const char*>(nl) - b);
          pos_ += len + 1;
          return emit(b, len, line);
        }
      }
      if (eof_) {
        if (pos_ < end_) {
          const char* b = buf_.data() + pos_;
          const std::size_t len = end_ - pos_;
          pos_ = end_;
          return emit(b, len, line);
        }
        return false;
      }
      fill();
    }
  }

  /// 1-based number of the line last returned by next().
  long long line_number() const { return line_number_; }
  /// True when reading stopped because of an I/O error rather than the end of the input.
  bool failed() const { return error_; }
  /// errno of the failed read, when failed().
  int error_code() const { return errno_; }

 private:
  bool emit(const char* b, std::size_t len, std::string_view& line) {
    if (len > 0 && b[len - 1] == '\r') --len;
    line = std::string_view(b, len);
    ++line_number_;
    return true;
  }

  void fill() {
    if (pos_ > 0) {
      std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
      end_ -= pos_;
      pos_ = 0;
    }
    if (end_ == buf_.size()) buf_.resize(buf_.size() * 2);
    if (before_read_) before_read_();
    char* dst = buf_.data() + end_;
    const std::size_t room = buf_.size() - end_;
    if (fd_ >= 0) {
      ssize_t n;
      do {
        n = ::read(fd_, dst, room);
      } while (n < 0 && errno == EINTR);
      if (n > 0) {
        end_ += static_cast<std::size_t>(n);
      } else {
        eof_ = true;
        if (n < 0) {
          error_ = true;
          errno_ = errno;
        }
      }
    } else if (in_ != nullptr) {
      const std::size_t n = std::fread(dst, 1, room, in_);
      end_ += n;
      if (n < room) {  // fread only returns short at the end of the input or on an error
        eof_ = true;
        if (std::ferror(in_)) {
          error_ = true;
          errno_ = errno;
        }
      }
    } else {
      eof_ = true;
    }
  }

  std::FILE* in_;
  int fd_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  bool eof_ = false, error_ = false;
  int errno_ = 0;
  long long line_number_ = 0;
  std::function<void()> before_read_;
};

}  // namespace tetia::app
