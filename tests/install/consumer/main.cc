// Uses the installed OCG: one object seen with neighbours, then missing, then removed.
#include <iostream>

#include "ocg/ocg/change_detector.h"

int main() {
  ocg::ObjectChangeDetector detector{ocg::OcgOptions{}};
  ocg::KeyframeObservation observation;
  observation.observed = {1, 2, 3};
  detector.Process(observation);
  std::cout << "objects " << detector.ObjectCount() << " edges " << detector.graph().EdgeCount()
            << "\n";
  return detector.graph().EdgeCount() == 3 ? 0 : 1;
}
