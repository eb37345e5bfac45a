"""The learning curve of ``bbgym baseline``: what it marks and what it says about seeds."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from bbgym.cli.baseline import (  # noqa: E402
    best_model_index,
    learning_curve_figure,
    plot_learning_curve,
)
from bbgym.cli.train import EVAL_SEED_OFFSET  # noqa: E402

STEPS = np.array([1000, 2000, 3000, 4000])
RETURNS = np.array([[1.0, 3.0], [6.0, 8.0], [4.0, 4.0], [5.0, 6.0]])  # means 2, 7, 4, 5.5
SUCCESSES = np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
RESULTS = {
    name: {
        "policy": name,
        "episodes": 10,
        "seeds": [0, 9],
        "success_rate": rate,
        "mean_return": ret,
    }
    for name, rate, ret in (("random", 0.1, -3.0), ("scripted", 0.9, 9.0), ("ppo", 0.7, 6.5))
}


def make_run(tmp_path: Path, steps=STEPS, returns=RETURNS, successes=SUCCESSES, log=None) -> Path:
    run = tmp_path / "run"
    (run / "eval").mkdir(parents=True)
    arrays = {"timesteps": steps, "results": returns, "ep_lengths": np.ones_like(returns)}
    if successes is not None:
        arrays["successes"] = successes
    np.savez(run / "eval" / "evaluations.npz", **arrays)
    if log is None:
        log = {"seed": 7, "best_model_timesteps": 2000, "best_mean_return": 7.0}
    (run / "train.json").write_text(json.dumps(log))
    return run


def legend_texts(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def line_labelled(ax, start: str):
    lines = [ln for ln in ax.get_lines() if ln.get_label().startswith(start)]
    assert len(lines) == 1, [ln.get_label() for ln in ax.get_lines()]
    return lines[0]


def test_learning_curve_marks_the_best_model_and_the_final_evaluation(tmp_path) -> None:
    import matplotlib.pyplot as plt

    fig = learning_curve_figure(make_run(tmp_path), RESULTS, "BeachballSail-v0")
    try:
        ax_success, ax_return = fig.axes[:2]
        for ax, values in (
            (ax_return, RETURNS.mean(axis=1)),
            (ax_success, 100 * SUCCESSES.mean(axis=1)),
        ):
            texts = legend_texts(ax)
            assert any("best model" in t for t in texts) and any("final" in t for t in texts)
            best = line_labelled(ax, "best model (best_model.zip)")
            assert list(best.get_xdata()) == [2000]  # train.json's best_model_timesteps
            assert list(best.get_ydata()) == pytest.approx([values[1]])
            final = line_labelled(ax, "final evaluation")
            assert list(final.get_xdata()) == [4000]
            assert list(final.get_ydata()) == pytest.approx([values[-1]])
            # The points' seeds: the eval env's base seed and the episodes per point...
            ppo = line_labelled(ax, "PPO evaluations")
            assert f"eval env seeded {7 + EVAL_SEED_OFFSET}" in ppo.get_label()
            assert "2 episodes per point" in ppo.get_label()
            # ...and the reference lines', from the baseline's own evaluation.
            for name in ("random", "scripted"):
                ref = line_labelled(ax, name)
                assert "seeds 0..9" in ref.get_label()
                assert ref.get_linestyle() == "--"
        random_line = line_labelled(ax_return, "random")
        assert list(random_line.get_ydata()) == [-3.0, -3.0]
        assert list(line_labelled(ax_success, "scripted").get_ydata()) == [90.0, 90.0]
        assert "7.0 at 2000 steps" in line_labelled(ax_return, "best model (").get_label()
        # One short line of title; what each point and line comes from is in the legends.
        title = fig._suptitle.get_text()
        assert title == "BeachballSail-v0: PPO while it learns, training seed 7"
        # The re-evaluated model stands right of the curve, not on its last point, and the
        # reference lines lie under the curve.
        reevaluated = line_labelled(ax_success, "best model re-evaluated")
        assert reevaluated.get_xdata()[0] > STEPS[-1]
        assert reevaluated.get_xdata()[0] < ax_success.get_xlim()[1]
        curve_z = line_labelled(ax_success, "PPO evaluations").get_zorder()
        assert line_labelled(ax_success, "scripted").get_zorder() < curve_z
        assert ax_success.get_ylim()[1] > 105  # a curve at 100% is not on the axis' edge
    finally:
        plt.close(fig)


def test_a_final_evaluation_that_is_the_best_model_gets_one_mark(tmp_path) -> None:
    import matplotlib.pyplot as plt

    returns = np.array([[1.0], [2.0], [3.0], [4.0]])
    run = make_run(tmp_path, returns=returns, log={"seed": 0, "best_model_timesteps": 4000})
    fig = learning_curve_figure(run, RESULTS, "BeachballSail-v0", evaluated="final")
    try:
        for ax in fig.axes[:2]:
            labels = [ln.get_label() for ln in ax.get_lines()]
            assert not any(label.startswith("best model (") for label in labels)
            assert not any(label.startswith("final evaluation:") for label in labels)
            both = line_labelled(ax, "final evaluation, also the best model")
            assert list(both.get_xdata()) == [4000]
            # No two marks at one place: each mark's (x, y) differs.
            marks = [
                (ln.get_xdata()[0], ln.get_ydata()[0])
                for ln in ax.get_lines()
                if len(ln.get_xdata()) == 1
            ]
            assert len(marks) == len(set(marks)) == 2, marks
    finally:
        plt.close(fig)


def test_best_model_without_train_log_entry_is_the_first_best_mean(tmp_path) -> None:
    import matplotlib.pyplot as plt

    returns = np.array([[1.0], [5.0], [5.0], [2.0]])
    assert best_model_index(STEPS, returns.mean(axis=1), {}) == 1
    assert best_model_index(STEPS, returns.mean(axis=1), {"best_model_timesteps": None}) == 1
    assert best_model_index(STEPS, returns.mean(axis=1), {"best_model_timesteps": 3000}) == 2
    assert best_model_index(STEPS, returns.mean(axis=1), {"best_model_timesteps": 3900}) == 3
    run = make_run(tmp_path, returns=returns, successes=None, log={"seed": 0})
    fig = learning_curve_figure(run, {}, "BeachballTopple-v0")
    try:
        ax_return = fig.axes[1]
        assert list(line_labelled(ax_return, "best model (").get_xdata()) == [2000]
        assert "eval env seeded 10000" in line_labelled(ax_return, "PPO").get_label()
        labels = [ln.get_label() for ln in ax_return.get_lines()]
        assert not any(label.startswith(("random", "scripted")) for label in labels)
    finally:
        plt.close(fig)


def test_learning_curve_of_a_single_evaluation(tmp_path) -> None:
    import matplotlib.pyplot as plt
    from PIL import Image

    run = make_run(
        tmp_path,
        steps=np.array([2048]),
        returns=np.array([[1.0, 3.0]]),
        successes=np.array([[1.0, 0.0]]),
        log={"seed": 3, "best_model_timesteps": 2048},
    )
    fig = learning_curve_figure(run, RESULTS, "BeachballSail-v0")
    try:
        for ax, value in zip(fig.axes[:2], (50.0, 2.0), strict=True):
            for start in ("final evaluation, also the best model", "PPO evaluations"):
                line = line_labelled(ax, start)
                assert list(line.get_xdata()) == [2048]
                assert list(line.get_ydata()) == pytest.approx([value])
            lo, hi = ax.get_xlim()
            assert lo < 2048 < hi and hi - lo >= 2048
    finally:
        plt.close(fig)
    out = tmp_path / "curve.png"
    plot_learning_curve(run, RESULTS, "BeachballSail-v0", out)
    with Image.open(out) as png:
        assert png.size[0] > 600
