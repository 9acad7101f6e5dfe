#include "ocg/io/time_order.h"

#include <algorithm>
#include <utility>

#include "ocg/io/text_lines.h"

namespace ocg {

TimeOrderCheck::TimeOrderCheck(std::string path, std::string item)
    : path_(std::move(path)), item_(std::move(item)) {}

void TimeOrderCheck::Add(double timestamp, const std::string& text, int line) {
  if (!entries_.empty() && !(timestamp > entries_.back().timestamp)) {
    const std::string rule = item_ + "s must be listed in strictly increasing time (sort the " +
                             "file by its first column; remove or correct repeated times)";
    // Every earlier time is in entries_, sorted, so a repeat is found wherever it was.
    const auto same =
        std::lower_bound(entries_.begin(), entries_.end(), timestamp,
                         [](const Entry& entry, double value) { return entry.timestamp < value; });
    if (same != entries_.end() && same->timestamp == timestamp) {
      ThrowParseError(path_, line,
                      item_ + " time " + text + " repeats line " + std::to_string(same->line) +
                          " ('" + same->text + "'): " + rule);
    }
    const Entry& previous = entries_.back();
    ThrowParseError(path_, line,
                    item_ + " time " + text + " is earlier than line " +
                        std::to_string(previous.line) + " ('" + previous.text + "'): " + rule);
  }
  entries_.push_back({timestamp, line, text});
}

}  // namespace ocg
