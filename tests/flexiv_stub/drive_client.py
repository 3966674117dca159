"""Drives the Mech-Mind client of a translated script against the fake vision server, for
tests/transpile_flexiv.rs (test data of krlkit).

    python3 drive_client.py SCRIPT HOST PORT PLAN

imports SCRIPT as a module (its main() does not run), connects its `robot` to the stub
flexivrdk, runs the steps of PLAN and prints one JSON document: [[step, result], ...], where a
result is what the method returned (poses and axes as lists) and the client's last_status.
"""

import importlib.util
import json
import sys

import flexivrdk

script, host, port, plan = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
spec = importlib.util.spec_from_file_location("translated", script)
mod = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mod)
mod.robot = mod.connect("stub")
mm = mod.mm
out = []


def step(name, value):
    out.append([name, {"value": value, "status": mm.last_status}])


if plan == "default":
    step("status before init", mm.get_status())
    step("init with a bad timeout", mm.init_socket(host, port, 0))
    step("init", mm.init_socket(host, port, 5))
    step("get_status", mm.get_status())
    step("switch_model", mm.switch_model(1, 2))
    step("switch_model bad recipe", mm.switch_model(1, 100))
    step("set_boxsize", mm.set_boxsize(1, 400, 300, 200))
    step("start_vis with the current pose", mm.start_vis(1, 0, 1, None))
    step("start_vis", mm.start_vis(1, 0, 0, mod.Axis()))
    step("get_visdata", mm.get_visdata(1))
    step("get_visdata bad job", mm.get_visdata(0))
    step("get_pose 2", mm.get_pose(2))
    step("get_pose 5", mm.get_pose(5))
    step("get_jps on poses", mm.get_jps(1))
    step("get_vispath joints", mm.get_vispath(1, 1))
    step("get_jps 2", mm.get_jps(2))
    step("start_vis again", mm.start_vis(1, 0, 0, mod.Axis()))
    step("get_dy_data", mm.get_dy_data(1))
    step("get_dypose 1", mm.get_dypose(1))
    step("start_viz", mm.start_viz(0, mod.Axis()))
    step("set_branch", mm.set_branch(1, 2))
    step("set_index", mm.set_index(2, 3))
    step("get_vizdata", mm.get_vizdata(2))
    step("start_viz again", mm.start_viz(0, mod.Axis()))
    step("get_plandata", mm.get_plandata(4))
    step("get_planpose 2", mm.get_planpose(2, 4))
    step("user_data", mm.user_data[1:4])
    step("plan_results", mm.plan_results[1:])
    step("get_planjps other format", mm.get_planjps(1, 3))
    step("get_dolist", mm.get_dolist())
    step("do_port", mm.do_port[1:5])
    step("set_dolist", mm.set_dolist())
    step("set_pos", mm.set_pos(mod.Pose(500, 0, 400, 0, 180, 0)))
elif plan == "faults":
    mm.init_socket(host, port, 5)
    step("get_status", mm.get_status())
    mm.reply_timeout = 0.1
    step("get_status late", mm.get_status())
    mm.reply_timeout = 5
    step("start_vis project running", mm.start_vis(1, 0, 0, mod.Axis()))
    step("get_visdata dropped", mm.get_visdata(1))
    step("switch_model garbage", mm.switch_model(1, 1))
    step("set_boxsize wrong echo", mm.set_boxsize(1, 1, 1, 1))
elif plan == "frames":
    # The script's pose maths against values worked out by hand (KUKA A, B, C = Z, Y', X'').
    P = mod.Pose
    step("compose rotations", mod.frame_mul(P(0, 0, 0, 30, 0, 0), P(0, 0, 0, 0, 20, 0)))
    step("compose offset", mod.frame_mul(P(100, 0, 0, 90, 0, 0), P(10, 0, 0, 0, 0, 0)))
    step("tool offset", mod.frame_mul(P(500, 0, 300, 0, 180, 0), P(0, 0, -80, 0, 0, 0)))
    p = P(512.5, -30, 250, 12, 33, -140)
    step("inverse", mod.frame_mul(p, mod.frame_inv(p)))
    step("gimbal lock", mod.frame_mul(P(0, 0, 0, 10, -90, 0), P(0, 0, 0, 0, 0, 0)))
    # A quaternion for A=40, B=-25, C=170 (reference formulas, half angles).
    a, b, c = (mod.math.radians(v) / 2 for v in (40, -25, 170))
    cos, sin = mod.math.cos, mod.math.sin
    q = [
        cos(a) * cos(b) * cos(c) + sin(a) * sin(b) * sin(c),
        cos(a) * cos(b) * sin(c) - sin(a) * sin(b) * cos(c),
        cos(a) * sin(b) * cos(c) + sin(a) * cos(b) * sin(c),
        sin(a) * cos(b) * cos(c) - cos(a) * sin(b) * sin(c),
    ]
    step("quaternion", mod.pose_from_flexiv([0.5, -0.25, 0.125] + q))
    step("coord", [list(x) if isinstance(x, list) else x for x in (lambda k: [k.position, k.orientation, k.ref_frame])(mod.to_coord(P(500, -250, 125, 40, -25, 170)))])
elif plan == "closed":
    mm.init_socket(host, port, 1)
    step("get_status", mm.get_status())
else:
    sys.exit("unknown plan " + plan)

print(json.dumps(out))
