// app/progress.hpp -- the progress line of the mesh commands on stderr: the phase by name
// (reading, intersection, solve, writing), with a bar, a percentage and a rate where the phase
// counts its work (the supermesh's source cells).
//
// Shown when stderr is a terminal (--progress forces it, --quiet silences it and the notes), and
// only once the run has lasted a second (TETIA_PROGRESS_DELAY seconds): a quick run prints
// nothing. On a terminal the line is
// redrawn in place at most ten times a second and cleared when the run ends; elsewhere (forced
// into a file or a pipe) one line per second at most. Notes (what was ignored or reoriented in a
// file) are printed as lines whenever the line is enabled. One instance per process, used from
// the main thread only (the supermesh calls its callback from the calling thread).
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace tetia::app {

class Progress {
 public:
  enum class Mode { automatic, always, never };

  static Progress& get() {
    static Progress p;
    return p;
  }

  void configure(Mode mode) {
    tty_ = isatty(fileno(stderr)) != 0;
    // TETIA_PROGRESS_DELAY: seconds before the line appears (default 1; the tests use 0).
    if (const char* d = std::getenv("TETIA_PROGRESS_DELAY"); d != nullptr && *d != '\0')
      delay_ = std::chrono::duration<double>(std::max(0.0, std::atof(d)));
    enabled_ = mode == Mode::always || (mode == Mode::automatic && tty_);
    notes_ = mode != Mode::never && (mode == Mode::always || tty_);
  }

  /// A new phase; `total` > 0: it counts `unit`s up to total (advance()).
  void phase(const std::string& name, std::size_t total = 0, const char* unit = "cells") {
    name_ = name;
    total_ = total;
    unit_ = unit;
    done_ = 0;
    phase_start_ = Clock::now();
    last_draw_ = {};
    draw(false);
  }

  void advance(std::size_t done) {
    if (done == done_) return;
    done_ = done;
    draw(total_ > 0 && done >= total_);  // the end of a counted phase is always shown
  }

  /// A line of information (shown whenever notes are: a terminal, or --progress).
  void note(const std::string& text) {
    if (!notes_) return;
    clear();
    std::fprintf(stderr, "tetia: %s\n", text.c_str());
    drawn_ = false;
  }

  /// Ends the line (the run is over, or output follows).
  void finish() { clear(); }

 private:
  using Clock = std::chrono::steady_clock;

  Progress() : start_(Clock::now()) {}

  void draw(bool force) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (now - start_ < delay_) return;  // a quick run shows nothing
    const auto every = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(1000);
    if (!force && last_draw_ != Clock::time_point{} && now - last_draw_ < every) return;
    last_draw_ = now;
    std::string line = "tetia: " + name_;
    if (total_ > 0) {
      const double f = static_cast<double>(done_) / static_cast<double>(total_);
      const int width = 24, full = static_cast<int>(f * width + 0.5);
      line += " [" + std::string(static_cast<std::size_t>(full), '#') + std::string(static_cast<std::size_t>(width - full), '.') + "]";
      char tail[96];
      const double secs = std::chrono::duration<double>(now - phase_start_).count();
      const double rate = secs > 0.0 ? static_cast<double>(done_) / secs : 0.0;
      std::snprintf(tail, sizeof tail, " %3.0f%%  %.3g %s/s", 100.0 * f, rate, unit_);
      line += tail;
    }
    if (tty_) {
      std::fprintf(stderr, "\r%s\033[K", line.c_str());
    } else {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    std::fflush(stderr);
    drawn_ = tty_;
  }

  void clear() {
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
  }

  bool enabled_ = false, notes_ = false, tty_ = false, drawn_ = false;
  std::string name_;
  std::size_t total_ = 0, done_ = 0;
  const char* unit_ = "cells";
  Clock::time_point start_, phase_start_, last_draw_;
  std::chrono::duration<double> delay_{1.0};
};

}  // namespace tetia::app
