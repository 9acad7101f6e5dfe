#include "ocg/io/time_order.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <numeric>
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

std::vector<std::size_t> OrderReferenceTimes(const std::string& path, const std::string& item,
                                             const std::vector<TimedLine>& lines) {
  // Lines out of order: counted as the lines whose time is earlier than the line before.
  std::size_t descents = 0;
  std::string first_descent;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (!(lines[i].timestamp < lines[i - 1].timestamp)) continue;
    if (descents++ == 0) {
      first_descent = "line " + std::to_string(lines[i].line) + ", time " + lines[i].text +
                      " after " + lines[i - 1].text + " at line " +
                      std::to_string(lines[i - 1].line);
    }
  }
  std::vector<std::size_t> order(lines.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (descents > 0) {
    std::stable_sort(order.begin(), order.end(), [&lines](std::size_t a, std::size_t b) {
      return lines[a].timestamp < lines[b].timestamp;
    });
    spdlog::warn("{}: {} {}{} listed before an earlier time (first: {}): sorted by time", path,
                 descents, item, descents == 1 ? "" : "s", first_descent);
  }
  // A time listed again: the stable sort put its lines in file order, the first is kept.
  std::vector<std::size_t> kept;
  kept.reserve(order.size());
  std::size_t repeats = 0;
  std::string examples;
  constexpr std::size_t kExamples = 3;
  for (const std::size_t index : order) {
    if (!kept.empty() && lines[kept.back()].timestamp == lines[index].timestamp) {
      if (repeats++ < kExamples) {
        const TimedLine& first = lines[kept.back()];
        examples += std::string(examples.empty() ? "" : "; ") + "line " +
                    std::to_string(lines[index].line) + " repeats line " +
                    std::to_string(first.line) + " ('" + first.text + "')";
      }
      continue;
    }
    kept.push_back(index);
  }
  if (repeats > 0) {
    spdlog::warn("{}: {} repeated {} time{} ({}{}): kept the first {} of each time", path, repeats,
                 item, repeats == 1 ? "" : "s", examples, repeats > kExamples ? "; ..." : "", item);
  }
  return kept;
}

}  // namespace ocg
