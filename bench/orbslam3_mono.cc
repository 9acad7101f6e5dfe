// Runs ORB-SLAM3 (v1.0, monocular, no viewer) over a TUM RGB-D folder, as the anchor our
// SLAM is compared with (docs/anchor_orbslam3.md). Not part of the project's build: it
// needs an ORB-SLAM3 build, and bench/orbslam3_anchor.sh compiles it against one.
//
//   orbslam3_mono VOCABULARY.txt SETTINGS.yaml SEQUENCE_DIR OUT_DIR [--no-pacing | --pace S]
//
// Frames are handed over at the pace of their timestamps (a frame tracked faster than the
// camera delivers waits for the next), as ORB-SLAM3's own examples do, so that its local
// mapping thread gets the time a live camera would give it; nothing is dropped. --pace S
// gives each frame S times its period (S > 1 on a loaded machine gives ORB-SLAM3's
// threads the time an idle one would); --no-pacing hands frames over at once.
//
// Writes into OUT_DIR:
//   states.txt                  timestamp and ORB-SLAM3's tracking state after each frame
//                               (2 = OK, 3 = recently lost, 4 = lost, 1 = not initialized)
//   CameraTrajectory.txt        TUM, camera to world: every frame ORB-SLAM3 keeps in its
//                               largest map (its SaveTrajectoryEuRoC: each frame relative to
//                               its reference keyframe's final pose) whose state was OK, once
//                               (a frame tracked without a pose repeats the previous frame's
//                               timestamp and pose in ORB-SLAM3's lists; only the first row
//                               of a timestamp is kept)
//   CameraTrajectoryAll.txt     the same without the OK filter (recently lost frames too)
//   KeyFrameTrajectory.txt      TUM, its keyframes
// and prints one line: frames, first OK frame, OK frames, maps.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "System.h"

namespace {

struct Frame {
  double timestamp = 0.0;
  std::string timestamp_text;
  std::string path;
};

std::vector<Frame> ReadTumList(const std::string& folder) {
  std::ifstream in(folder + "/rgb.txt");
  if (!in) throw std::runtime_error("cannot read " + folder + "/rgb.txt");
  std::vector<Frame> frames;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Frame frame;
    fields >> frame.timestamp_text >> frame.path;
    if (frame.path.empty()) continue;
    frame.timestamp = std::stod(frame.timestamp_text);
    frame.path = folder + "/" + frame.path;
    frames.push_back(frame);
  }
  return frames;
}

// The frame whose timestamp is nearest t (within 1 ms), or -1.
int NearestFrame(const std::vector<Frame>& frames, double t) {
  int best = -1;
  double best_gap = 1e-3;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const double gap = std::abs(frames[i].timestamp - t);
    if (gap <= best_gap) {
      best_gap = gap;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: orbslam3_mono VOCABULARY.txt SETTINGS.yaml SEQUENCE_DIR OUT_DIR "
                 "[--no-pacing | --pace S]\n";
    return 2;
  }
  const std::string vocabulary = argv[1], settings = argv[2], folder = argv[3], out = argv[4];
  double pace = 1.0;
  try {
    for (int a = 5; a < argc; ++a) {
      const std::string option = argv[a];
      if (option == "--no-pacing") {
        pace = 0.0;
      } else if (option == "--pace" && a + 1 < argc) {
        pace = std::stod(argv[++a]);
        if (!(pace > 0.0)) throw std::runtime_error("--pace wants a positive factor");
      } else {
        throw std::runtime_error("unknown option " + option + " (--no-pacing or --pace S)");
      }
    }
    const std::vector<Frame> frames = ReadTumList(folder);
    if (frames.empty()) throw std::runtime_error("no frames in " + folder + "/rgb.txt");
    ORB_SLAM3::System slam(vocabulary, settings, ORB_SLAM3::System::MONOCULAR,
                           /*bUseViewer=*/false);
    std::vector<int> states;
    int first_ok = -1, ok = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const cv::Mat image = cv::imread(frames[i].path, cv::IMREAD_UNCHANGED);
      if (image.empty()) throw std::runtime_error("cannot read " + frames[i].path);
      const auto start = std::chrono::steady_clock::now();
      slam.TrackMonocular(image, frames[i].timestamp);
      const double spent =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const int state = slam.GetTrackingState();
      states.push_back(state);
      if (state == 2) {
        ++ok;
        if (first_ok < 0) first_ok = static_cast<int>(i);
      }
      if (pace > 0.0 && i + 1 < frames.size()) {
        const double period = pace * (frames[i + 1].timestamp - frames[i].timestamp);
        if (spent < period)
          std::this_thread::sleep_for(std::chrono::duration<double>(period - spent));
      }
    }
    slam.Shutdown();
    const std::string euroc = out + "/trajectory_euroc.txt";
    slam.SaveTrajectoryEuRoC(euroc);
    slam.SaveKeyFrameTrajectoryTUM(out + "/KeyFrameTrajectory.txt");

    std::ofstream states_file(out + "/states.txt");
    states_file << "# timestamp state (ORB-SLAM3 Tracking::eTrackingState; 2 = OK)\n";
    for (std::size_t i = 0; i < frames.size(); ++i)
      states_file << frames[i].timestamp_text << ' ' << states[i] << '\n';

    // EuRoC rows carry nanoseconds; TUM rows get the list's own timestamp text back.
    std::ifstream in(euroc);
    std::ofstream all(out + "/CameraTrajectoryAll.txt"), tracked(out + "/CameraTrajectory.txt");
    std::string line;
    int rows = 0, kept = 0;
    std::vector<bool> written(frames.size(), false);
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      double nanoseconds = 0.0;
      if (!(fields >> nanoseconds)) continue;
      const int index = NearestFrame(frames, nanoseconds * 1e-9);
      if (index < 0) throw std::runtime_error("no frame at " + line);
      if (written[static_cast<std::size_t>(index)]) continue;
      written[static_cast<std::size_t>(index)] = true;
      std::string rest;
      std::getline(fields, rest);
      const std::string row = frames[static_cast<std::size_t>(index)].timestamp_text + rest + "\n";
      all << row;
      ++rows;
      if (states[static_cast<std::size_t>(index)] == 2) {
        tracked << row;
        ++kept;
      }
    }
    std::printf(
        "orbslam3_mono: %zu frames, first OK frame %d, OK %d, in the largest map %d (%d of them "
        "OK)\n",
        frames.size(), first_ok, ok, rows, kept);
  } catch (const std::exception& error) {
    std::cerr << "orbslam3_mono: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
