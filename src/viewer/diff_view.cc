#include "ocg/viewer/diff_view.h"

namespace ocg {
namespace {

constexpr int kUnjudged = 0;  // drawn light grey: unchanged
constexpr int kObserved = 1;  // drawn green: new at its place

ObjectView View(const ObjectRecord& record, int state, bool removed) {
  return {record.id, record.class_id, record.cuboid, removed ? 5 : state, removed};
}

}  // namespace

DiffScenes MakeDiffScenes(const MapDiff& diff, const MapScene& background) {
  DiffScenes scenes;
  scenes.before = background;
  scenes.before.objects.clear();
  scenes.before.moves.clear();
  scenes.after = scenes.before;
  for (const MoveLink& link : diff.unchanged) {
    scenes.before.objects.push_back(View(link.from, kUnjudged, false));
    scenes.after.objects.push_back(View(link.to, kUnjudged, false));
  }
  for (const ObjectRecord& record : diff.removed) {
    scenes.before.objects.push_back(View(record, kUnjudged, false));
    scenes.after.objects.push_back(View(record, kUnjudged, true));
  }
  for (const MoveLink& link : diff.moved) {
    scenes.before.objects.push_back(View(link.from, kUnjudged, false));
    scenes.after.objects.push_back(View(link.from, kUnjudged, true));
    scenes.after.objects.push_back(View(link.to, kObserved, false));
    scenes.after.moves.emplace_back(link.from.cuboid.centre, link.to.cuboid.centre);
  }
  for (const ObjectRecord& record : diff.added)
    scenes.after.objects.push_back(View(record, kObserved, false));
  return scenes;
}

}  // namespace ocg
