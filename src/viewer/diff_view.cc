#include "ocg/viewer/diff_view.h"

namespace ocg {
namespace {

ObjectView View(const ObjectRecord& record, bool removed) {
  return {record.id, record.class_id, record.cuboid, removed ? 5 : record.state, removed};
}

void Add(MapScene& scene, const ObjectView& view, const std::string& note = "") {
  scene.objects.push_back(view);
  scene.notes.resize(scene.objects.size());
  scene.notes.back() = note;
}

}  // namespace

DiffScenes MakeDiffScenes(const MapDiff& diff, const MapScene& background) {
  DiffScenes scenes;
  scenes.before = background;
  scenes.before.objects.clear();
  scenes.before.notes.clear();
  scenes.before.moves.clear();
  scenes.after = scenes.before;
  for (const MoveLink& link : diff.unchanged) {
    Add(scenes.before, View(link.from, false));
    Add(scenes.after, View(link.to, false));
  }
  for (const ObjectRecord& record : diff.removed) {
    Add(scenes.before, View(record, false));
    Add(scenes.after, View(record, true));
  }
  for (const MoveLink& link : diff.moved) {
    Add(scenes.before, View(link.from, false));
    Add(scenes.after, View(link.from, true));
    Add(scenes.after, View(link.to, false), "moved here");
    scenes.after.moves.emplace_back(link.from.cuboid.centre, link.to.cuboid.centre);
  }
  for (const ObjectRecord& record : diff.added) Add(scenes.after, View(record, false), "added");
  return scenes;
}

}  // namespace ocg
