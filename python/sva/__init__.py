"""sva: tactile object recognition and localization by spatially-varying appearance.

The C++ engine (module ``sva._sva_core``) with the C++ names::

    import sva
    train, test = sva.simulate("tiny", train=20, test=8, seed=1)
    m = sva.train(train)
    engine = sva.Engine(m, backend="auto")          # the map uploaded once, shared by the sessions
    for o, name in enumerate(m.object_names):      # one session per object: its touches only
        rec = sva.Recognizer(engine)
        for sample in test:
            if sample.object == o and sample.converged:  # add_reading refuses unconverged readings
                rec.add_reading(sample.reading)
        est = rec.estimate()                        # est.ready is False if no reading was added
        print(name, est.object_name, est.object_probability.max(), est.pose.T)  # pose.R, pose.T: NumPy

Batch recognition of a sessions file: :func:`sva.recognize_batch`, on one machine, and
:func:`sva.distributed.recognize_batch`, sharded over a Dask cluster. See docs/python.md.
"""

from pathlib import Path as _Path

from ._sva_core import (
    BatchRecognizer,
    CandidateTouch,
    ControllerStatus,
    Dataset,
    Engine,
    Error,
    Estimate,
    Hypothesis,
    Map,
    ObjectEvidence,
    PoseHypothesis,
    PosePrior,
    PoseSpaceKind,
    PoseSpaceSpec,
    Prior,
    Reading,
    Recognizer,
    RigidPose,
    Sample,
    Scene,
    SensorSpec,
    TouchPlan,
    TouchPlanner,
    TouchScore,
    TrainReport,
    assets_dir,
    load_scene,
    parse_scene,
    placed_pose_space,
    plan_next_touch,
    pose_space_around,
    show_progress,
    simulate,
    train,
)
from ._sva_core import __version__, _set_assets_dir
from .batch import Session, read_sessions, recognize_batch, trial_session

__all__ = [
    "BatchRecognizer",
    "CandidateTouch",
    "ControllerStatus",
    "Dataset",
    "Engine",
    "Error",
    "Estimate",
    "Hypothesis",
    "Map",
    "ObjectEvidence",
    "PoseHypothesis",
    "PosePrior",
    "PoseSpaceKind",
    "PoseSpaceSpec",
    "Prior",
    "Reading",
    "Recognizer",
    "RigidPose",
    "Sample",
    "Scene",
    "SensorSpec",
    "TouchPlan",
    "TouchPlanner",
    "TouchScore",
    "TrainReport",
    "assets_dir",
    "evaluate",
    "load_scene",
    "parse_scene",
    "placed_pose_space",
    "plan_next_touch",
    "pose_space_around",
    "Session",
    "read_sessions",
    "recognize_batch",
    "trial_session",
    "show_progress",
    "simulate",
    "train",
]



def __getattr__(name: str):
    # sva.evaluate is the tools' module's (sva._sva_eval: evaluation and figures, which link cairo): imported on first
    # use, so that `import sva`, all a robot's program needs, loads the engine alone.
    if name == "evaluate":
        from ._sva_eval import evaluate

        globals()["evaluate"] = evaluate
        return evaluate
    raise AttributeError(f"module 'sva' has no attribute {name!r}")


def __dir__() -> list:
    return sorted(set(globals()) | {"evaluate"})


# An installed wheel carries the built-in scenes and objects beside this file; the engine looks there (unless
# SVA_ASSETS says otherwise). In the build tree there is no such folder and the source tree's assets are used.
_packaged_assets = _Path(__file__).resolve().parent / "assets"
if (_packaged_assets / "scenes").is_dir():
    _set_assets_dir(str(_packaged_assets))
