#pragma once
// Timestamps of a frame list (TUM rgb.txt, EuRoC mav0/cam0/data.csv, the --frames list of
// `ocg_slam objects`) or of a trajectory must strictly increase down the file: a frame
// listed out of order gives the trajectories a step back in time, and two frames with one
// timestamp read the same detection file and give one time two poses.

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

}  // namespace ocg
