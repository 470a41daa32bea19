"""sva.plot: the command line's figures through matplotlib, from what sva eval writes."""

import json

import pytest

import sva
import sva.plot

pytest.importorskip("matplotlib")


def test_curves_draw_the_summarys_points(tiny, tmp_path):
    summary = json.loads(tiny.eval_json.read_text())
    fig = sva.plot.curves(summary, tiny.eval_json, labels=["this run", "the same from its file"])
    axes = fig.axes
    assert len(axes) == 4
    accuracy = axes[0].lines[0]
    assert list(accuracy.get_xdata()) == [p["readings"] for p in summary["curve"]]
    assert list(accuracy.get_ydata()) == [100 * p["accuracy"] for p in summary["curve"]]
    assert len(axes[0].lines) == 2  # the compared run on the same axes
    for suffix in ("png", "svg"):
        fig.savefig(tmp_path / f"curves.{suffix}")
        assert (tmp_path / f"curves.{suffix}").stat().st_size > 1000


def test_reliability_and_confusion(tiny, tmp_path):
    from conftest import run_sva

    summary = json.loads(tiny.eval_json.read_text())
    fig = sva.plot.reliability(summary)
    bins = summary["calibration"]["reliability"]
    assert len(fig.axes[1].patches) == len(bins)  # the counts, one bar per bin
    assert [p.get_height() for p in fig.axes[1].patches] == [b["count"] for b in bins]
    conf = tmp_path / "c.json"
    run_sva("eval", "--map", str(tiny.map), "--data", str(tiny.test), "--trials", "4", "--max-readings", "5",
            "--backend", "cpu", "--confusion", str(conf), "--confusion-at", "2,5")
    fig = sva.plot.confusion(conf, readings=2)
    assert "at 2 readings" in fig.axes[0].get_title()
    data = json.loads(conf.read_text())
    image = fig.axes[0].images[0].get_array()
    assert image.shape == (len(data["confusion"][0]["truths"]), len(data["confusion"][0]["estimates"]))
    with pytest.raises(ValueError, match=r"no matrix at 3 readings \(there are \[2, 5\]\)"):
        sva.plot.confusion(conf, readings=3)


def test_bad_input_is_named(tmp_path):
    with pytest.raises(ValueError, match="nope.json: cannot read"):
        sva.plot.curves(tmp_path / "nope.json")
    (tmp_path / "x.json").write_text("{not json")
    with pytest.raises(ValueError, match="x.json: not JSON"):
        sva.plot.reliability(tmp_path / "x.json")
    with pytest.raises(ValueError, match="without a 'curve'"):
        sva.plot.curves({"trials": 3})
