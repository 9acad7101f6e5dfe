"""tools/move_failures.py on a constructed sequence and run: each ground-truth move gets the
kind the run's change log, object map and OCG say."""
import json
import os
import subprocess
import sys

CUP, MOUSE, BOTTLE, VASE, BOWL = 41, 64, 39, 75, 45
SIZES = {CUP: 0.1, MOUSE: 0.11, BOTTLE: 0.24, VASE: 0.22, BOWL: 0.16}
NAMES = {CUP: "cup", MOUSE: "mouse", BOTTLE: "bottle", VASE: "vase", BOWL: "bowl"}
# Ground truth: id -> (class, old place, new place, frames showing the new place).
MOVES = {
    1: (CUP, (0.0, 0.0, 0.8), (1.0, 0.0, 0.8), 40),
    2: (MOUSE, (0.0, 1.0, 0.77), (1.0, 1.0, 0.77), 40),
    3: (MOUSE, (0.0, 2.0, 0.77), (1.0, 2.0, 0.77), 40),
    4: (BOTTLE, (0.0, 3.0, 0.87), (1.0, 3.0, 0.87), 40),
    5: (VASE, (0.0, 4.0, 0.86), (1.0, 4.0, 0.86), 40),
    6: (BOWL, (0.0, 5.0, 0.79), (1.0, 5.0, 0.79), 40),
    7: (CUP, (0.0, 6.0, 0.8), (1.0, 6.0, 0.8), 0),  # to a place no frame shows: no move
    8: (CUP, (0.0, 7.0, 0.8), (1.0, 7.0, 0.8), 40),
}


def write_sequence(folder):
    os.makedirs(folder)
    objects = []
    for gt_id, (class_id, old, new, in_view) in MOVES.items():
        size = SIZES[class_id]
        objects.append({"class": NAMES[class_id], "class_id": class_id, "id": gt_id,
                        "shape": "box", "size": [size, size, size], "status": "moved",
                        "history": [{"centre": list(old), "frames_in_view": 50, "present": True,
                                     "time": 1000.0, "yaw": 0.0},
                                    {"centre": list(new), "frames_in_view": in_view,
                                     "present": True, "time": 1030.0, "yaw": 0.0}]})
    with open(os.path.join(folder, "objects_gt.json"), "w") as handle:
        json.dump({"objects": objects, "scene": "test", "seed": 1, "time_origin": 1000.0}, handle)


def cuboid(class_id, centre):
    size = SIZES[class_id]
    return {"centre": list(centre), "size": [size, size, size], "yaw": 0.0}


def live_object(object_id, class_id, centre):
    return {"class": NAMES[class_id], "class_id": class_id, "cuboid": cuboid(class_id, centre),
            "doubt": 0.0, "first_seen": 1000.0, "first_session": 0, "id": object_id,
            "last_seen": 1050.0, "last_session": 0, "map_points": 0, "observations": 30,
            "state": 1, "yaw_from": "boxes"}


def change(kind, object_id, class_id, centre, to=None):
    entry = {"centroid": list(centre), "class": NAMES[class_id], "class_id": class_id,
             "cuboid": cuboid(class_id, centre), "object_id": object_id, "type": kind}
    if to is not None:
        entry["to"] = {"cuboid": cuboid(class_id, to[1]), "first_seen": 1040.0, "object_id": to[0]}
    return entry


def write_run(folder):
    os.makedirs(folder)
    near = lambda p: (p[0] + 0.02, p[1], p[2])  # within half of every object's extent
    # The cup's move reported right; the two mice swapped (each to the other's new place);
    # the bottle still mapped at its old place, suspicious with doubt 80 (removed once and
    # restored); the vase never mapped; the bowl removed with no move; the second cup moved
    # to the first cup's new place.
    changes = [
        change("moved", 10, CUP, near(MOVES[1][1]), (20, near(MOVES[1][2]))),
        change("moved", 11, MOUSE, near(MOVES[2][1]), (22, near(MOVES[3][2]))),
        change("moved", 12, MOUSE, near(MOVES[3][1]), (21, near(MOVES[2][2]))),
        change("removed", 13, BOWL, near(MOVES[6][1])),
        change("merged", 14, VASE, near(MOVES[5][1])),  # a merged duplicate is no run object
        change("removed", 15, BOTTLE, MOVES[4][1]),
        change("restored", 15, BOTTLE, MOVES[4][1]),
        change("moved", 17, CUP, near(MOVES[8][1]), (20, near(MOVES[1][2]))),
    ]
    live = [live_object(20, CUP, near(MOVES[1][2])), live_object(21, MOUSE, near(MOVES[2][2])),
            live_object(22, MOUSE, near(MOVES[3][2])), live_object(15, BOTTLE, MOVES[4][1])]
    nodes = [{"id": 15, "class_id": BOTTLE, "doubt": 80.0, "state": 4}]
    for name, content in (("changes.json", {"changes": changes}),
                          ("objects.json", {"format": "ocg-objects", "objects": live,
                                            "up": [0, 0, 1], "version": 1}),
                          ("ocg.json", {"nodes": nodes})):
        with open(os.path.join(folder, name), "w") as handle:
            json.dump(content, handle)


def test_each_move_gets_its_kind(source_dir, tmp_path):
    sequence, run = str(tmp_path / "sequence"), str(tmp_path / "run")
    write_sequence(sequence)
    write_run(run)
    result = subprocess.run(
        [sys.executable, os.path.join(source_dir, "tools", "move_failures.py"), run, sequence],
        capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "%s: 7 moves, 1 right" % run, result.stdout
    kinds = {int(line.split()[0]): line for line in lines[1:-1]}
    assert sorted(kinds) == [1, 2, 3, 4, 5, 6, 8], result.stdout  # 7 moved out of every view
    assert kinds[1].endswith("right: object 10 to 20")
    assert "paired wrong: object 11 to 22" in kinds[2] and kinds[2].endswith("swapped with 3")
    assert "paired wrong: object 12 to 21" in kinds[3] and kinds[3].endswith("swapped with 2")
    assert kinds[4].endswith("still mapped: object 15, suspicious, doubt 80 > 50")
    assert kinds[5].endswith("vase           never mapped")
    assert kinds[6].endswith("removed, unpaired: object 13")
    assert "paired wrong: object 17 to 20" in kinds[8]
    assert kinds[8].endswith("to the new place of 1")
    assert lines[-1] == ("never mapped 1, paired wrong 3, removed, unpaired 1, right 1, "
                         "still mapped 1")


def test_a_doubt_within_tau_is_said_so(source_dir, tmp_path):
    sequence, run = str(tmp_path / "sequence"), str(tmp_path / "run")
    write_sequence(sequence)
    write_run(run)
    result = subprocess.run(
        [sys.executable, os.path.join(source_dir, "tools", "move_failures.py"), "--tau-doubt",
         "100", run, sequence], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "still mapped: object 15, suspicious, doubt 80 <= 100" in result.stdout
