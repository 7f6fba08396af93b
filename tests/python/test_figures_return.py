"""Issue 31 item 5: loop labels follow the step's action, no blank panel, every *_plot returns its Figure."""
import inspect
from types import SimpleNamespace

import matplotlib.figure
import numpy as np
import pytest

from drillpy.figures import control, frf, loop, records, simulation, stochastic


def test_loop_steps_are_labelled_by_their_action(tmp_path):
    ev = SimpleNamespace(E_train=0.3, E_test=0.25)
    steps = [SimpleNamespace(action=a, effect=e, after=ev) for a, e in
             (("add", "bit_hysteresis"), ("remove", "bit_hysteresis"), ("recalibrate", "string_stiffness"))]
    fig = loop.errors_plot(tmp_path / "errors.png", SimpleNamespace(baseline=ev, steps=steps, rounds=[]))
    assert [t.get_text() for t in fig.axes[0].get_xticklabels()] == [
        "baseline", "+ bit_hysteresis (added)", "- bit_hysteresis (removed)", "~ string_stiffness (recalibrated)"]
    assert (tmp_path / "errors.png").stat().st_size > 0


@pytest.mark.parametrize("speeds, wobs", [([8.0, 12.0, 16.0], [245e3]), ([16.0], [200e3, 245e3, 290e3])])
def test_a_one_row_control_map_is_drawn_as_curves(tmp_path, speeds, wobs):
    maps = {"ideal": np.array([[1.2, 0.6, 0.2]]), "z_torque": np.array([[0.3, np.inf, 0.1]])}
    if len(speeds) == 1:
        maps = {k: v.T for k, v in maps.items()}
    study = SimpleNamespace(comparison={k: {"map": v} for k, v in maps.items()},
                            validation_window=SimpleNamespace(speeds=np.array(speeds), wobs=np.array(wobs)))
    fig = control.maps_plot(tmp_path / "maps.png", study)
    (ax,) = fig.axes
    curves = {ln.get_label(): ln.get_ydata() for ln in ax.lines}
    np.testing.assert_array_equal(curves["ideal"], [1.2, 0.6, 0.2])  # the SS drawn, not a blank shading
    assert "z_torque: stalled" in curves  # the stalled run marked, not dropped


def test_every_plot_returns_its_figure_and_draws_without_a_file(tmp_path):
    fig = simulation.severity_plot(None, [6.0, 7.0, 8.0], [1.3, 0.9, 0.2], 7.5)
    assert isinstance(fig, matplotlib.figure.Figure) and list(tmp_path.iterdir()) == []
    assert any(np.allclose(ln.get_xdata(), 7.5) for ln in fig.axes[0].lines)  # the threshold drawn
    written = simulation.severity_plot(tmp_path / "s.png", [6.0, 7.0], [1.3, 0.2])
    assert isinstance(written, matplotlib.figure.Figure) and (tmp_path / "s.png").stat().st_size > 0
    plots = [f for m in (control, frf, loop, records, simulation, stochastic)
             for n, f in inspect.getmembers(m, inspect.isfunction) if n.endswith("_plot") and f.__module__ == m.__name__]
    assert len(plots) >= 25
    assert [f.__name__ for f in plots if inspect.signature(f).return_annotation != "plt.Figure"] == []
