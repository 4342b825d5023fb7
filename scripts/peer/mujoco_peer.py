#!/usr/bin/env python3
"""The same robot and motion in MuJoCo, timed: reads what `peer_trace` wrote
(DIR/peer.json, DIR/targets.csv, DIR/robot.urdf), builds the MuJoCo model from
the URDF (a free joint on the root link, a floor plane, a position servo per
joint with the testbed's gains and torque limits, the robot's own geoms
colliding with the floor only, as the testbed's do), replays the recorded
servo targets as position targets, and reports MuJoCo's physics-only step in
microseconds (best of several `mujoco.rollout` runs, a C loop), its contact
points per step, and the robot's speed over the second half of the walk.
Prints one JSON line.

A robot read from an MJCF file (peer.json's `mjcf`) is built from that file
as MuJoCo reads it instead (its joints' damping, friction loss and armature,
its geoms' friction and contact settings, its options), with three changes:
its visual geoms go (their meshes are not in the repository), its world's
geoms go (the floor is the peer's), and its actuators and keyframes go (the
testbed's position servos drive the joints, as in the testbed).

    python3 scripts/peer/mujoco_peer.py target/peer [--integrator implicitfast|euler]

Needs `pip install mujoco==4.0.0` (not part of the required tests).
"""

import argparse
import json
import os
import sys
import time

import mujoco
import numpy as np
from mujoco import rollout


def from_mjcf(path):
    """The MJCF model as MuJoCo reads it, less what the testbed supplies itself."""
    spec = mujoco.MjSpec.from_file(path)
    for g in list(spec.geoms):
        if (g.contype == 0 and g.conaffinity == 0) or g.parent == spec.worldbody:
            spec.delete(g)
    used = {g.meshname for g in spec.geoms}
    for m in list(spec.meshes):
        if m.name not in used:
            spec.delete(m)
    for element in list(spec.actuators) + list(spec.keys):
        spec.delete(element)
    return spec


def build(peer, urdf, integrator, solref):
    mjcf = peer.get("mjcf")
    spec = from_mjcf(mjcf) if mjcf else mujoco.MjSpec.from_file(urdf)
    spec.option.timestep = peer["dt_s"]
    spec.option.integrator = {
        "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
        "euler": mujoco.mjtIntegrator.mjINT_EULER,
    }[integrator]
    root = spec.body(peer["root_link"])
    if root is None:
        sys.exit(f"MuJoCo's model has no body {peer['root_link']!r}")
    if not mjcf:
        root.add_freejoint()
        # The robot's geoms touch the floor only (the testbed disables self-contacts).
        for geom in spec.geoms:
            geom.contype, geom.conaffinity = 1, 0
            geom.friction = [peer["friction"], 0.005, 0.0001]
            geom.solref = [solref, 1.0]
    spec.worldbody.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[20.0, 20.0, 0.1],
        contype=0,
        conaffinity=1,
        friction=[peer["friction"], 0.005, 0.0001],
        solref=[solref, 1.0],
    )
    for name, effort in zip(peer["joints"], peer["effort_nm"]):
        a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        a.set_to_position(kp=peer["kp_nm_per_rad"], kv=peer["kd_nm_s_per_rad"])
        if effort is None:  # a continuous joint whose URDF gives no limit
            a.forcelimited = mujoco.mjtLimited.mjLIMITED_FALSE
        else:
            a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            a.forcerange = [-effort, effort]
    return spec.compile()


def start(model, data, peer):
    mujoco.mj_resetData(model, data)
    x, y, z, w = peer["start_orientation_xyzw"]
    free = model.joint(model.body(peer["root_link"]).jntadr[0]).qposadr[0]
    data.qpos[free : free + 3] = peer["start_position_m"]
    data.qpos[free + 3 : free + 7] = [w, x, y, z]
    for name, angle in zip(peer["joints"], peer["start_joints_rad"]):
        data.qpos[model.joint(name).qposadr[0]] = angle
    data.ctrl[:] = peer["start_joints_rad"]
    mujoco.mj_forward(model, data)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("dir")
    p.add_argument("--integrator", default="implicitfast", choices=["implicitfast", "euler"])
    p.add_argument("--repeats", type=int, default=5)
    # MuJoCo's default contact time constant (0.02 s) is too soft for a small
    # robot at 4 ms steps: the ERS-7 slides on its spheres and walks 0.4 m of
    # the 2.8 m it walks in the testbed; at 0.01 s it walks 1.8 m open loop.
    p.add_argument("--solref", type=float, default=0.01, help="contact time constant, s")
    args = p.parse_args()
    peer = json.load(open(os.path.join(args.dir, "peer.json")))
    targets = np.loadtxt(os.path.join(args.dir, "targets.csv"), delimiter=",", ndmin=2)
    model = build(peer, os.path.join(args.dir, peer["urdf"]), args.integrator, args.solref)
    data = mujoco.MjData(model)
    steps = targets.shape[0]

    # Contacts and uprightness, stepping in Python (not timed).
    start(model, data, peer)
    contacts, upright = 0, True
    root = model.body(peer["root_link"]).id
    half = peer.get("half_step", steps // 2)
    for k in range(steps):
        data.ctrl[:] = targets[k]
        mujoco.mj_step(model, data)
        contacts += data.ncon
        upright &= bool(data.xmat[root].reshape(3, 3)[2, 2] > 0.5)
        if k + 1 == half:
            half_x = float(data.xpos[root][0])
    travelled = float(data.xpos[root][0] - peer["start_position_m"][0])
    second_half = 1000.0 * (float(data.xpos[root][0]) - half_x) / ((steps - half) * peer["dt_s"])

    # The physics-only step, timed in MuJoCo's own C loop.
    start(model, data, peer)
    state = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    control = targets[np.newaxis, :, :]
    best = float("inf")
    with rollout.Rollout(nthread=0) as r:
        for _ in range(args.repeats):
            began = time.perf_counter()
            r.rollout(model, data, state[np.newaxis, :], control)
            best = min(best, time.perf_counter() - began)
    print(json.dumps({
        "mujoco": mujoco.__version__,
        "integrator": args.integrator,
        "solref_s": args.solref,
        "us_per_step": 1e6 * best / steps,
        "contacts_per_step": contacts / steps,
        "upright": upright,
        "travelled_m": travelled,
        "second_half_mm_s": second_half,
        "model": "MJCF" if peer.get("mjcf") else "URDF",
        "steps": steps,
    }))


if __name__ == "__main__":
    main()
