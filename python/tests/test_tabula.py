"""The package against the library it binds: kinematics round trips, stable poses of a
box, cloud files, perception of a simulated frame, PDDL, a job in the simulator, and bad
input as exceptions."""

from pathlib import Path

import numpy as np
import pytest

import tabula

ROOT = Path(__file__).resolve().parents[2]


def test_fk_ik_round_trip_on_every_builtin_arm():
    for name in ["wam", "pr2", "golem3"]:
        robot = tabula.Robot(name)
        n = len(robot.joint_names())
        lo, hi = robot.limits().T
        lo = np.where(np.isfinite(lo), lo, -1.0)
        hi = np.where(np.isfinite(hi), hi, 1.0)
        q = lo + (hi - lo) * np.random.default_rng(3).uniform(0.3, 0.7, n)
        T = robot.fk(q)
        assert T.shape == (4, 4) and np.allclose(T[3], [0, 0, 0, 1])
        solutions = robot.ik(T, seed=q)
        assert solutions, name
        for s in solutions:
            assert np.allclose(robot.fk(s), T, atol=1e-4), name


def test_jacobian_matches_finite_differences():
    robot = tabula.Robot("wam")
    q = np.full(len(robot.joint_names()), 0.3)
    J = robot.jacobian(q)
    eps = 1e-6
    for k in range(len(q)):
        dq = q.copy()
        dq[k] += eps
        d = (robot.fk(dq)[:3, 3] - robot.fk(q)[:3, 3]) / eps
        assert np.allclose(J[:3, k], d, atol=1e-5)


def test_unreachable_targets_give_no_solution_and_bad_input_raises():
    robot = tabula.Robot("golem3")
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    assert robot.ik(far) == []
    with pytest.raises(ValueError, match="joints"):
        robot.fk([0.0, 1.0])
    with pytest.raises(ValueError, match="finite"):
        robot.fk([np.nan] * len(robot.joint_names()))
    with pytest.raises(ValueError, match="shape"):
        robot.ik(np.eye(3))
    with pytest.raises(ValueError):
        tabula.Robot("no_such_robot")


def test_stable_poses_of_a_box_rest_on_their_faces():
    x, y, z = 0.1, 0.06, 0.02
    v = np.array([[i * x, j * y, k * z] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
    f = np.array([
        [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
        [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
    ])
    T, p, m = tabula.stable_poses(v, f)
    assert T.shape[1:] == (4, 4) and len(p) == len(T) == len(m) == 6
    assert np.isclose(p.sum(), 1.0, atol=1e-6) and np.all(np.diff(p) <= 1e-12)
    for t in T:
        rested = v @ t[:3, :3].T + t[:3, 3]
        assert np.isclose(rested[:, 2].min(), 0.0, atol=1e-9)
        assert np.allclose(rested.mean(axis=0)[:2], 0.0, atol=1e-9)
    # The likeliest poses lie on the largest faces (z = ±0.02).
    assert np.isclose(abs((T[0] @ [0, 0, 1, 0])[2]), 1.0)
    with pytest.raises(ValueError, match="shape"):
        tabula.stable_poses(v[:, :2], f)
    with pytest.raises(ValueError, match="outside"):
        tabula.stable_poses(v, f + 10)


def test_cloud_files_and_perception_of_a_simulated_table(tmp_path):
    scene = tabula.Scene(ROOT / "scenes" / "clutter.toml")
    scene.settle()
    points, world_from_camera = scene.capture()
    assert points.ndim == 3 and points.shape[2] == 3
    out = tabula.perceive(points, world_from_camera=world_from_camera)
    assert out["objects"] and out["table"]["points"] > 1000
    assert out["labels"].shape == points.shape[:2]
    assert (out["labels"] == 0).sum() == out["table"]["points"]
    # PCL's convention beside it: object k of the JSON has label k.
    assert out["segments"].shape == points.shape[:2] and out["segments"].dtype == np.uint32
    for o in out["objects"]:
        assert (out["segments"] == o["label"]).sum() == o["points"]
    cloud, colors, viewpoint = tabula.read_cloud(ROOT / "data" / "real" / "kinect_laptop_box.pcd")
    assert cloud.shape == (480, 640, 3) and viewpoint.shape == (4, 4)
    assert np.isnan(cloud).any() and np.isfinite(cloud).any()
    with pytest.raises(ValueError, match="shape"):
        tabula.perceive(np.zeros((10, 2)))
    with pytest.raises(ValueError):
        tabula.read_pcd(tmp_path / "missing.pcd")


def test_plan_pddl_plans_and_says_when_there_is_none():
    domain = (ROOT / "pddl" / "tablewclear-domain.pddl").read_text()
    problem = (ROOT / "pddl" / "thesis6-a.pddl").read_text()
    plan = tabula.plan_pddl(domain, problem)
    assert plan and all(a.startswith("(") for a in plan)
    with pytest.raises(ValueError):
        tabula.plan_pddl(domain, "(define (problem p) (:domain other))")


def test_a_table_cleared_from_python_is_judged_by_physics():
    scene = tabula.Scene(ROOT / "scenes" / "clutter.toml")
    out = scene.clear()
    assert out["success"] and out["verdict"]["in_bin"] == out["verdict"]["objects"]
    # The scene moved on: the table is empty now.
    again = scene.clear()
    assert again["verdict"]["objects"] == 0


def test_the_other_jobs_from_python():
    placed = tabula.Scene(ROOT / "scenes" / "pr2_holding.toml").place()
    assert placed["success"] and placed["verdict"]["surface"] == "table"
    shelves = tabula.Scene(ROOT / "scenes" / "golem_shelves.toml")
    moved = shelves.pick_place([0.556, -0.663, 1.07], [0.82, -0.2, 1.01])
    assert moved["success"] and moved["verdict"]["target_error"] < 0.03
    tidied = tabula.Scene(ROOT / "scenes" / "tidy.toml").tidy()
    assert tidied["moved"] == tidied["objects"] > 0 and not tidied["verdict"]["knocked"]
    with pytest.raises(ValueError, match="pick"):
        shelves.pick_place([0.5, np.nan, 1.0], [0.8, -0.2, 1.0])


def test_a_urdf_file_with_its_srdf():
    urdf = ROOT / "data" / "mbm" / "panda" / "panda.urdf"
    if not urdf.exists():
        pytest.skip("no Panda in data/mbm")
    robot = tabula.Robot(urdf)
    q = np.array([0.1, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])[: len(robot.joint_names())]
    T = robot.fk(q)
    assert any(np.allclose(robot.fk(s), T, atol=1e-4) for s in robot.ik(T, seed=q))


def test_plan_motion_answers_as_motion_plan_does():
    panda = ROOT / "data" / "mbm" / "panda"
    robot = tabula.Robot(panda / "panda.urdf")
    scene = panda / "problems" / "table_pick_panda" / "scene0001.yaml"
    request = panda / "problems" / "table_pick_panda" / "request0001.yaml"
    # A MotionBenchMaker problem, by its scene and request files.
    out = tabula.plan_motion(robot, scene, request=request)
    assert out["solved"] and len(out["joint_names"]) == 7
    times = [p["time"] for p in out["points"]]
    assert times[0] == 0.0 and times == sorted(times) and out["duration"] == times[-1]
    # Named states, joints and a pose; the robot by its file.
    named = tabula.plan_motion(robot, scene, start="ready", goal="extended")
    assert named["path"][0][3] == -2.356 and named["path"][-1][3] == 0.0
    goal = np.array(named["path"][-1])
    joints = tabula.plan_motion(str(panda / "panda.urdf"), scene, start="ready", goal=goal)
    assert joints["solved"] and np.allclose(joints["path"][-1], goal)
    T = robot.fk(np.array(named["path"][0]))
    posed = tabula.plan_motion(robot, None, start=goal, goal=T, seed=3)
    assert posed["solved"] and np.allclose(robot.fk(np.array(posed["path"][-1])), T, atol=1e-4)
    # No motion is an answer, not an exception: a goal out of reach.
    far = T.copy()
    far[2, 3] += 3.0
    blocked = tabula.plan_motion(robot, scene, start="ready", goal=far, timeout=0.2)
    assert not blocked["solved"] and blocked["reason"] == "unreachable" and blocked["message"]
    # A wrong query raises, naming what is wrong.
    with pytest.raises(ValueError, match="no planning group `arm`"):
        tabula.plan_motion(robot, scene, goal="ready", group="arm")
    with pytest.raises(ValueError, match="7 values"):
        tabula.plan_motion(robot, scene, goal=[0.0, 1.0])
    with pytest.raises(ValueError, match="finite"):
        tabula.plan_motion(robot, scene, goal=[0.0, np.nan, 0, 0, 0, 0, 0])
    with pytest.raises(ValueError, match="give a goal"):
        tabula.plan_motion(robot, scene)
    with pytest.raises(ValueError, match="padding"):
        tabula.plan_motion(robot, scene, goal="ready", params={"world": {"padding": -1.0}})


def test_perception_parameters_from_a_dict_or_a_file(tmp_path):
    scene = tabula.Scene(ROOT / "scenes" / "clutter.toml")
    scene.settle()
    points, world_from_camera = scene.capture()
    usual = tabula.perceive(points, world_from_camera=world_from_camera)
    # Objects need 100,000 points: none of the cups on the table has that many.
    strict = {"min_object_points": 100000}
    none = tabula.perceive(points, world_from_camera=world_from_camera, params=strict)
    assert usual["objects"] and not none["objects"]
    path = tmp_path / "perception.toml"
    path.write_text("min_object_points = 100000\n")
    from_file = tabula.perceive(points, world_from_camera=world_from_camera, params=path)
    assert not from_file["objects"]
    with pytest.raises(ValueError, match="min_object_points"):
        tabula.perceive(points, params={"min_object_points": -5})
    with pytest.raises(ValueError, match="params"):
        tabula.perceive(points, params={"min_object_points": float("nan")})
    with pytest.raises(ValueError, match="unknown field"):
        tabula.perceive(points, params={"no_such_key": 1})
