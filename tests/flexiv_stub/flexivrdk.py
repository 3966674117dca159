"""A stand-in for the Flexiv RDK Python package (flexivrdk), for running translated scripts
without a robot (reference notes, Flexiv section 3.6). It is test data of krlkit, not Flexiv
code: it implements only what the scripts call, checks the API shape of the RDK version named
by FLEXIV_STUB_RDK (default 1.6), and records every call.

Environment:
  FLEXIV_STUB_LOG     file that receives the recorded calls as JSON when the script ends
  FLEXIV_STUB_RDK     RDK version whose API shape is checked (1.6: SetDigitalOutputs(list, list),
                      JPos.q; 1.7 and later: SetDigitalOutputs(dict), JPos.q_m)
  FLEXIV_STUB_INPUTS  digital input ports that read True, e.g. "9,10" (default: none)
  FLEXIV_STUB_FAULT   "1": the robot starts with a fault that ClearFault clears
  FLEXIV_STUB_WORK    JSON {"name": [x, y, z, rx, ry, rz]} (m, Euler ZYX degrees as a Coord
                      lists them): the work coordinates WorkCoord(robot).pose(name) reads
  FLEXIV_STUB_FAST    "1": time.sleep does not sleep but advances time.monotonic and is
                      recorded as {"call": "sleep", "sec": s} (equivalence runs)

The joints (RobotStates.q) follow the MoveJ targets (JPos in degrees); the TCP pose
(RobotStates.tcp_pose) follows the MoveL/MovePTP targets (in WORLD, in a work
coordinate, or relative to the start in the tool), so a script that reads it back sees where
the robot went.
"""

import atexit
import enum
import json
import math
import os

import time

_RDK = tuple(int(x) for x in os.environ.get("FLEXIV_STUB_RDK", "1.6").split(".")[:2])
_LOG = []
_PORTS = 18


def _record(call, **args):
    _LOG.append(dict(call=call, **args))


if os.environ.get("FLEXIV_STUB_FAST") == "1":
    _clock = [time.monotonic()]

    def _sleep(sec):
        _record("sleep", sec=sec)
        _clock[0] += sec

    time.sleep = _sleep
    time.monotonic = lambda: _clock[0]

_WORK = json.loads(os.environ.get("FLEXIV_STUB_WORK", "{}"))


def _rot(rx, ry, rz):
    """Euler ZYX degrees (listed rx, ry, rz) as a rotation matrix."""
    a, b, c = math.radians(rz), math.radians(ry), math.radians(rx)
    ca, sa, cb, sb, cc, sc = math.cos(a), math.sin(a), math.cos(b), math.sin(b), math.cos(c), math.sin(c)
    return [
        [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
        [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
        [-sb, cb * sc, cb * cc],
    ]


def _frame(pos, ori):
    return (list(pos), _rot(*ori))


def _mul(f, g):
    (p, r), (q, s) = f, g
    m = [[sum(r[i][k] * s[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    t = [p[i] + sum(r[i][k] * q[k] for k in range(3)) for i in range(3)]
    return (t, m)


def _quat(f):
    """[x, y, z, qw, qx, qy, qz] of a frame."""
    t, m = f
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = [0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s]
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        q = [(m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s]
    elif m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        q = [(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s]
    else:
        s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
        q = [(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s]
    return list(t) + q


def _work(name):
    if name not in _WORK:
        raise KeyError("work coordinate %r is not defined on this robot" % name)
    v = _WORK[name]
    return _frame(v[:3], v[3:])


_TCP = [_frame([0.5, 0.0, 0.3], [180.0, 0.0, 0.0])]
_Q = [[0.0, -0.7, 0.0, 1.57, 0.0, 0.7, 0.0]]


def _moved(target):
    """The TCP after a move to `target` (a Coord)."""
    f = _frame(target.position, target.orientation)
    kind, name = target.ref_frame
    if kind == "WORLD":
        _TCP[0] = f
    elif kind == "WORK":
        _TCP[0] = _mul(_work(name), f)
    elif kind == "TRAJ" and name == "START":
        _TCP[0] = _mul(_TCP[0], f)
    else:
        raise ValueError("ref_frame %r is not modelled" % (target.ref_frame,))


class WorkCoord:
    def __init__(self, robot):
        self._robot = robot

    def pose(self, name):
        return _quat(_work(name))


@atexit.register
def _write_log():
    path = os.environ.get("FLEXIV_STUB_LOG")
    if path:
        with open(path, "w") as f:
            json.dump(_LOG, f, indent=1)


class Mode(enum.Enum):
    UNKNOWN = 0
    IDLE = 1
    RT_JOINT_TORQUE = 2
    RT_JOINT_IMPEDANCE = 3
    NRT_JOINT_IMPEDANCE = 4
    RT_JOINT_POSITION = 5
    NRT_JOINT_POSITION = 6
    NRT_PLAN_EXECUTION = 7
    NRT_PRIMITIVE_EXECUTION = 8
    RT_CARTESIAN_MOTION_FORCE = 9
    NRT_CARTESIAN_MOTION_FORCE = 10


class Coord:
    def __init__(self, position, orientation, ref_frame, ref_q_m=None, ref_q_e=None):
        if len(position) != 3 or len(orientation) != 3 or len(ref_frame) != 2:
            raise ValueError("Coord(position[3], orientation[3], ref_frame[2])")
        self.position = [float(v) for v in position]
        self.orientation = [float(v) for v in orientation]
        self.ref_frame = list(ref_frame)

    def to_json(self):
        return {"position": self.position, "orientation": self.orientation, "ref_frame": self.ref_frame}


class JPos:
    def __init__(self, q_m, q_e=None):
        if len(q_m) != 7:
            raise ValueError("JPos needs the 7 arm joints of a Rizon")
        values = [float(v) for v in q_m]
        if _RDK >= (1, 7):
            self.q_m = values
        else:
            self.q = values
        self.q_e = list(q_e or [])

    def to_json(self):
        return {"q_m" if _RDK >= (1, 7) else "q": self.q_m if _RDK >= (1, 7) else self.q}


def _json(v):
    if hasattr(v, "to_json"):
        return v.to_json()
    if isinstance(v, (list, tuple)):
        return [_json(x) for x in v]
    return v


class RobotStates:
    def __init__(self):
        self.q = list(_Q[0])
        self.tcp_pose = _quat(_TCP[0])
        self.flange_pose = [0.5, 0.0, 0.4, 0.0, 1.0, 0.0, 0.0]


class Tool:
    def __init__(self, robot):
        self._robot = robot

    def Switch(self, name):
        if self._robot._mode != Mode.IDLE:
            raise RuntimeError("tools can only be switched in IDLE")
        _record("Tool.Switch", name=name)


class Robot:
    def __init__(self, serial_number, network_interface_whitelist=None):
        _record("Robot", serial=serial_number)
        self._fault = os.environ.get("FLEXIV_STUB_FAULT") == "1"
        self._enabled = False
        self._mode = Mode.IDLE
        ports = os.environ.get("FLEXIV_STUB_INPUTS", "")
        on = {int(p) for p in ports.split(",") if p.strip()}
        self._inputs = [p in on for p in range(_PORTS)]

    def fault(self):
        return self._fault

    def ClearFault(self, timeout_sec=30):
        _record("ClearFault")
        self._fault = False
        return True

    def Enable(self):
        _record("Enable")
        self._enabled = True

    def operational(self, verbose=True):
        if _RDK >= (1, 7) and verbose is not True:
            raise TypeError("operational() takes no arguments in RDK 1.7+")
        return self._enabled and not self._fault

    def SwitchMode(self, mode):
        if not isinstance(mode, Mode):
            raise TypeError("SwitchMode needs a flexivrdk.Mode")
        if not self.operational():
            raise RuntimeError("not operational")
        _record("SwitchMode", mode=mode.name)
        self._mode = mode

    def ExecutePrimitive(self, name, params, properties=None, block_until_started=True):
        if self._mode != Mode.NRT_PRIMITIVE_EXECUTION:
            raise RuntimeError("ExecutePrimitive needs NRT_PRIMITIVE_EXECUTION")
        if properties is not None and _RDK >= (1, 7):
            raise TypeError("RDK 1.7+ has no properties argument")
        _record("ExecutePrimitive", primitive=name, params={k: _json(v) for k, v in params.items()})
        if isinstance(params.get("target"), Coord):
            _moved(params["target"])
        elif isinstance(params.get("target"), JPos):
            j = params["target"]
            _Q[0] = [math.radians(v) for v in (j.q_m if _RDK >= (1, 7) else j.q)]

    def primitive_states(self):
        return {"reachedTarget": 1}

    def SetDigitalOutputs(self, *args):
        if _RDK >= (1, 7):
            if len(args) != 1 or not isinstance(args[0], dict):
                raise TypeError("RDK 1.7+: SetDigitalOutputs({port: value})")
            ports = {int(k): bool(v) for k, v in args[0].items()}
        else:
            if len(args) != 2 or not isinstance(args[0], list) or len(args[0]) != len(args[1]):
                raise TypeError("RDK 1.6: SetDigitalOutputs(port_list, value_list)")
            ports = {int(k): bool(v) for k, v in zip(*args)}
        for p in ports:
            if not 0 <= p < _PORTS:
                raise ValueError("port %d outside 0-%d" % (p, _PORTS - 1))
        _record("SetDigitalOutputs", ports={str(k): v for k, v in sorted(ports.items())})

    def digital_inputs(self):
        return list(self._inputs)

    def SetVelocityScale(self, velocity_scale):
        if not 0 <= velocity_scale <= 100:
            raise ValueError("velocity scale outside 0-100")
        _record("SetVelocityScale", scale=velocity_scale)

    def states(self):
        return RobotStates()

    def Stop(self):
        _record("Stop")
        self._mode = Mode.IDLE
