#pragma once
// Two rules for the times of a file's lines, by what the file is.
//
// The INPUTS of a run (TUM rgb.txt, EuRoC mav0/cam0/data.csv, the --frames list of
// `ocg_slam objects`) must strictly increase down the file: a frame listed out of order
// gives the trajectories a step back in time, and two frames with one timestamp read the
// same detection file and give one time two poses. TimeOrderCheck refuses them.
//
// REFERENCE poses (ground truth in TUM or EuRoC format, trajectories given to map along or
// to evaluate) are read as the field's own tools read them: TUM's associate.py keys the
// lines by time (any order; one entry per time) and evo takes them as they come. The
// official fr2_desk ground truth lists one time on two lines. OrderReferenceTimes sorts and
// keeps the first pose of a repeated time, and says so once per file.

#include <cstddef>
#include <string>
#include <vector>

namespace ocg {

// Fed the timestamps of a file's data lines in file order; throws at the first one that
// is not later than all before it.
class TimeOrderCheck {
 public:
  // path: the file, for the messages; item: what a line holds ("frame", "pose").
  TimeOrderCheck(std::string path, std::string item);

  // timestamp in seconds, text as written in the file, line 1-based. Throws ParseError
  //   "path:line: frame time T repeats line L ('T'): ..."       (the same time again), or
  //   "path:line: frame time T is earlier than line L ('T2'): ..." (L: the previous line).
  void Add(double timestamp, const std::string& text, int line);

 private:
  struct Entry {
    double timestamp;
    int line;
    std::string text;
  };
  std::string path_;
  std::string item_;
  std::vector<Entry> entries_;  // strictly increasing: Add throws before breaking that
};

// One data line of a reference file: its time in seconds, the time's text as written, and
// its 1-based line number.
struct TimedLine {
  double timestamp = 0.0;
  std::string text;
  int line = 0;
};

// The indices into lines of the entries to use, in strictly increasing time: lines out of
// order are sorted (stable), a time listed again keeps its first line (in file order).
// Warns once per kind, naming path, the lines and the count:
//   "path: 1 repeated pose time (line 10863 repeats line 10862 ('1311868229.5760')): kept
//    the first pose of each time"
//   "path: 3 poses listed before an earlier time (first: line 7, time 1.2 after 1.4 at line
//    6): sorted by time"
// item names what a line holds ("pose").
std::vector<std::size_t> OrderReferenceTimes(const std::string& path, const std::string& item,
                                             const std::vector<TimedLine>& lines);

}  // namespace ocg
