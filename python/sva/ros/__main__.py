"""``python -m sva.ros export``: one session of a sessions file (docs/batch-format.md) replayed into an MCAP bag of
ROS 2 messages (sva.ros). Sessions files come from a robot's recordings, from ``sva recognize --write-sessions``
(evaluation trials with their truth) or any tool that writes the format; the bag's estimates are those
``sva recognize`` gives for the same session."""

from __future__ import annotations

import argparse
import sys
from typing import Optional, Sequence

from .. import Error, Map, Recognizer, load_scene, read_sessions, trial_session
from . import export_session, scene_meshes


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m sva.ros", description=__doc__)
    sub = p.add_subparsers(dest="command", required=True)
    e = sub.add_parser("export", help="write one session's estimates, touches and object as an MCAP bag",
                       description="Replays one session of a sessions file through a recognizer and writes, at "
                       "each reading, vision_msgs/Detection3DArray (/sva/detections), geometry_msgs/"
                       "PoseWithCovarianceStamped (/sva/pose), visualization_msgs/MarkerArray of the touches "
                       "(/sva/touches) and of the best object's mesh at its pose (/sva/object). docs/ros.md.")
    e.add_argument("--map", required=True, help="map file (sva train)")
    source = e.add_mutually_exclusive_group(required=True)
    source.add_argument("--sessions", help="sessions file (JSON Lines, docs/batch-format.md)")
    source.add_argument("--data", help="test dataset: the session is evaluation trial --trial, as sva eval runs it")
    e.add_argument("--trial", type=int, default=0, help="with --data: which trial, from 0 (default 0)")
    e.add_argument("--seed", type=int, default=1, help="with --data: the trials' seed (default 1, as sva eval)")
    e.add_argument("--max-readings", type=int, default=30, help="with --data: readings per trial (default 30)")
    e.add_argument("--out", required=True, help="the MCAP file to write")
    which = e.add_mutually_exclusive_group()
    which.add_argument("--session", type=int, default=0, help="which session, from 0 in file order (default 0)")
    which.add_argument("--id", help="the session with this id")
    e.add_argument("--frame", default="world", help="frame_id of every message: the readings' robot frame")
    e.add_argument("--stamps", choices=("auto", "recorded", "period"), default="auto",
                   help="the readings' stamps: recorded (the session's truth.stamps_s, which sva replay "
                   "--write-session writes), period (--start + i --period), auto (recorded where the session has "
                   "them; default)")
    e.add_argument("--period", type=float, default=0.5, help="seconds between readings' stamps (default 0.5)")
    e.add_argument("--start", type=float, default=0.0, help="stamp of the first reading, seconds (default 0)")
    e.add_argument("--top", type=int, default=5, help="hypotheses per detection (default 5)")
    e.add_argument("--scene", help="scene of the map's objects, for their meshes and boxes (default: the map's "
                   "built-in scene)")
    e.add_argument("--mesh", choices=("on", "off"), default="on", help="the best object's mesh on /sva/object")
    e.add_argument("--backend", choices=("auto", "cpu", "vulkan"), default="auto", help="vote backend")
    return p


def _meshes(args: argparse.Namespace, m: Map):
    if args.mesh == "off":
        return None
    name = args.scene or m.scene_name
    try:
        scene = load_scene(name)
    except Error as e:
        if args.scene:
            raise
        print(f"sva.ros: no meshes ({e}); pass --scene FILE, or --mesh off", file=sys.stderr)
        return None
    if list(scene.object_names) != list(m.object_names):
        raise Error(f"{name}: its objects {scene.object_names} are not the map's {m.object_names}")
    return scene_meshes(scene)


def _stamps(args: argparse.Namespace, session) -> Optional[list]:
    recorded = session.truth.get("stamps_s") if isinstance(session.truth, dict) else None
    if args.stamps == "period" or (args.stamps == "auto" and recorded is None):
        return None
    if not isinstance(recorded, list) or len(recorded) != len(session.readings):
        raise Error(f"{args.sessions or args.data}: session {session.id!r} has no truth.stamps_s with one time per "
                    "reading (sva replay --write-session writes them); use --stamps period")
    try:
        return [round(float(t) * 1e9) + round(args.start * 1e9) for t in recorded]
    except (TypeError, ValueError):
        where = args.sessions or args.data
        raise Error(f"{where}: session {session.id!r}: truth.stamps_s holds a non-number") from None


def _export(args: argparse.Namespace) -> int:
    if args.period <= 0 or args.start < 0 or args.top < 1:
        raise Error("sva.ros export: --period must be > 0, --start >= 0 and --top >= 1")
    m = Map.load(args.map)
    if args.data is not None:
        session = trial_session(args.data, m, args.trial, seed=args.seed, max_readings=args.max_readings)
        return _write(args, m, session)
    sessions = read_sessions(args.sessions, m)
    if args.id is not None:
        picked = [s for s in sessions if s.id == args.id]
        if not picked:
            raise Error(f"{args.sessions}: no session with id {args.id!r}")
        session = picked[0]
    elif not 0 <= args.session < len(sessions):
        raise Error(f"{args.sessions}: session {args.session} out of range ({len(sessions)} sessions)")
    else:
        session = sessions[args.session]
    return _write(args, m, session)


def _write(args: argparse.Namespace, m: Map, session) -> int:
    stamps = _stamps(args, session)
    rec = Recognizer(m, backend=args.backend)
    summary = export_session(rec, session.readings, args.out, frame_id=args.frame,
                             start_ns=round(args.start * 1e9), period_ns=round(args.period * 1e9), top_k=args.top,
                             detection_id=session.id, meshes=_meshes(args, m), stamps_ns=stamps)
    n = max(summary["readings"], 1)
    print(f"wrote {args.out}: session {session.id!r}, {summary['readings']} readings, "
          + ", ".join(f"{c} on {t}" for t, c in summary["messages"].items())
          + f"; {summary['bytes']} bytes ({summary['bytes'] / n:.0f} per reading)")
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = _parser().parse_args(argv)
    try:
        return _export(args)
    except Error as e:
        print(f"sva.ros: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
