"""The figure check (imunav.plotting.check_figure) catches each defect it names, on a figure
built with exactly that defect, and passes the same figure without it."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from imunav import plotting as P  # noqa: E402

T = np.linspace(0.0, 10.0, 400)


@pytest.fixture(autouse=True)
def book_style():
    with matplotlib.rc_context(P.BOOK_RC):
        yield
    plt.close("all")


def clean():
    """A figure that passes: two distinct curves, one unit, readable names."""
    fig, ax = P.figure()
    ax.plot(T, np.sin(T), **P.styled("increments/coning2"))
    ax.plot(T, np.cos(T), **P.styled("increments/poly8_m6"))
    ax.set(xlabel="t (s)", ylabel="attitude error (deg)", title="two algorithms")
    ax.set_xlim(0, 15)                       # room on the right for the legend
    ax.legend(loc="center right")
    return fig, ax


def one(problems, word):
    assert len(problems) == 1 and word in problems[0], problems
    return problems[0]


def test_the_clean_figure_passes():
    fig, _ = clean()
    assert P.check_figure(fig) == []


def test_a_line_hidden_under_another():
    fig, ax = clean()
    ax.plot(T, np.sin(T), **P.styled("increments/ignagni4"))    # drawn over coning2
    msg = one(P.check_figure(fig), "hidden under")
    assert "'two-sample coning' is hidden under 'Ignagni 4-sample'" in msg


def test_a_line_that_differs_within_a_fraction_of_its_width_is_hidden_too():
    fig, ax = clean()
    ax.plot(T, np.sin(T) * (1 + 1e-4), **P.styled("increments/ignagni4"))
    one(P.check_figure(fig), "hidden under")


def test_hidden_is_excused_when_the_label_says_they_coincide():
    fig, ax = clean()
    ax.plot(T, np.sin(T), **P.styled("increments/ignagni4", label="Ignagni 4-sample "
                                     "(coincides with two-sample coning)"))
    ax.get_legend().remove()
    fig.legend(loc="outside lower center", ncols=2)   # a legend this long covers the curves
    assert P.check_figure(fig) == []


def test_a_wide_translucent_underlay_and_a_dashed_line_on_top_are_not_hidden():
    fig, ax = P.figure()
    ax.plot(T, np.sin(T), **P.styled("truth", lw=3, alpha=0.35))
    ax.plot(T, np.sin(T), **P.styled("estimate", lw=1.2))              # dashed, on top
    ax.plot(T, np.cos(T), **P.styled("increments/coning2"))
    ax.plot(T, np.cos(T), **P.styled("increments/poly8_m6", lw=1.2, ls="--"))
    ax.set(xlabel="t (s)", ylabel="x (m)", xlim=(0, 15))
    ax.legend(loc="center right")
    assert P.check_figure(fig) == []


def test_an_opaque_band_drawn_over_a_line_hides_it():
    fig, ax = clean()
    ax.fill_between(T, -2, 2, color="0.8", zorder=3)
    assert sum("hidden under" in p for p in P.check_figure(fig)) == 2


def test_more_than_eight_legend_entries():
    fig, ax = clean()
    for k in range(7):
        ax.plot(T, np.sin(T) + k + 2, color=P.DISTINCT[k], label=f"offset {k + 2}")
    ax.get_legend().remove()
    fig.legend(loc="outside right upper")
    one(P.check_figure(fig), "legend with 9 entries")


def test_two_units_on_one_axis():
    fig, ax = P.figure()
    ax.semilogy(T, 1 + T, label="position (m)")
    ax.semilogy(T, 1 + T ** 2, label="velocity (m/s)")
    ax.set(xlabel="t (s)", title="error norm")
    ax.legend()
    msg = one(P.check_figure(fig), "2 units on one y axis")
    assert "m ('position (m)')" in msg and "m/s ('velocity (m/s)')" in msg


def test_a_line_whose_unit_is_not_the_axis_unit():
    fig, ax = clean()
    ax.plot(T, T, color="black", label="rate (deg/s)")
    ax.legend()
    one(P.check_figure(fig), "units on one y axis")


@pytest.mark.parametrize("where", ["title", "ylabel", "legend", "xtick"])
@pytest.mark.parametrize("text", ["poly8_m6", "fig1a, A=dcm", "gyro.noise_density", "series4"])
def test_internal_ids(where, text):
    fig, ax = clean()
    if where == "title":
        ax.set_title(text)
    elif where == "ylabel":
        ax.set_ylabel(f"{text} (deg)")
    elif where == "legend":
        ax.lines[0].set_label(text)
        ax.legend()
    else:
        ax.set_xticks([2, 5], ["t", text])
    problems = P.check_figure(fig)
    assert problems and all("internal id" in p for p in problems), problems


def test_math_and_device_names_are_not_internal_ids():
    fig, ax = clean()
    ax.set_title(r"$\omega_b$ of the MPU-6050 and the x-IMU3, DCM vs quaternion")
    assert P.check_figure(fig) == []


def test_small_text():
    fig, ax = clean()
    ax.tick_params(labelsize=6)
    ax.legend(fontsize=7)
    problems = P.check_figure(fig)
    assert any("tick labels at 6 pt" in p for p in problems)
    assert any("legends at 7 pt" in p for p in problems)


def test_too_wide_and_too_coarse():
    fig, ax = clean()
    fig.set_size_inches(11, 4)
    assert one(P.check_figure(fig), "in wide")
    fig, ax = clean()
    fig.set_dpi(100)
    one(P.check_figure(fig), "100 dpi")


def test_a_legend_outside_the_axes_counts_in_the_width():
    fig, ax = plt.subplots(figsize=(6.5, 3))       # no constrained layout to make room
    ax.plot(T, np.sin(T), **P.styled("increments/coning2"))
    ax.set(xlabel="t (s)", ylabel="attitude error (deg)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    one(P.check_figure(fig), "in wide")


def test_a_sliver_of_a_panel():
    fig, ax = clean()
    ax.plot(T, 1e-3 * T, color="black", label="slope (deg)")
    ax.set_aspect(1000)
    ax.legend()
    assert any("panel" in p for p in P.check_figure(fig))


def test_a_fixed_range_that_leaves_the_axes_empty():
    fig, ax = clean()
    ax.set_ylim(-10, 10)
    one(P.check_figure(fig), "fixed y range")
    fig, ax = clean()
    ax.set_ylim(-1.2, 1.2)
    assert P.check_figure(fig) == []


def test_show_raises_once_installed():
    P.install_figure_check()
    P.install_figure_check()           # twice is once
    fig, ax = clean()
    ax.set_title("poly8_m6")
    with pytest.raises(P.FigureCheckError, match="internal id 'poly8_m6'"):
        plt.show()
    assert plt.get_fignums() == []     # closed: the next cell starts clean
    clean()
    plt.show()                         # a clean figure shows


def test_warn_mode_prints_and_shows(capsys):
    P.install_figure_check("warn")
    try:
        fig, ax = clean()
        ax.set_title("poly8_m6")
        plt.show()
        assert "figure check: figure" in capsys.readouterr().err
    finally:
        P.install_figure_check()


def test_names_and_colours_hold_for_every_thing():
    assert P.name("poly8_m6") == P.name("increments/poly8_m6") == "8-node fit + Magnus-6"
    assert P.name("not an id") == "not an id"
    with pytest.raises(KeyError, match="both kinds"):
        P.colour("first_order")
    for thing in P.THINGS:
        assert not P.internal_ids_in(P.name(thing)), thing
    # within each group drawn together, the colours differ
    for _, ids in P.ALGORITHM_GROUPS:
        assert len({P.colour(i) for i in ids}) == len(ids)
    for triad in ("gyro", "accel"):
        terms = [k for k in P.THINGS if k.startswith(triad + ".")]
        assert len({P.colour(k) for k in terms}) == len(terms)
    presets = ["ideal", "BNO055", "MPU-6050", "BMI088", "ADIS16470", "tactical"]
    assert len({P.colour(k) for k in presets}) == len(presets)


def test_3d_axes_are_not_judged_by_2d_geometry():
    fig = plt.figure(figsize=(4, 4))
    ax = fig.add_subplot(projection="3d")
    ax.plot([0, 0.3], [0, 0.2], [0, 0.1], color="black", label="body x axis")
    ax.set(xlim=(-1.1, 1.1), ylim=(-1.1, 1.1), zlim=(-1.1, 1.1))
    ax.legend()
    assert P.check_figure(fig) == []


# ------------------------------------------------------------------ dotted lines out of sight

def test_a_dotted_reference_on_its_own_solid_curve_is_hidden():
    """A documented-order line drawn dotted exactly on the measured curve of the same colour
    (notebook 06's convergence figure): a reader sees one solid line."""
    fig, ax = clean()
    ax.plot(T, np.sin(T), ":", color=P.colour("increments/coning2"), lw=1)
    msg = one(P.check_figure(fig), "lies on the solid line 'two-sample coning'")
    assert "dotted line (unlabelled" in msg


def test_a_dotted_reference_drawn_apart_passes():
    fig, ax = clean()
    ax.plot(T, np.sin(T) - 0.4, ":", color=P.colour("increments/coning2"), lw=1)
    # and a dotted line on a solid one of *another* colour shows its dots
    ax.plot(T, np.cos(T), ":", color=P.colour("increments/coning2"), lw=1)
    assert P.check_figure(fig) == []


def test_an_unlabelled_dashed_line_under_a_solid_one_is_hidden():
    fig, ax = clean()
    ax.lines[1].remove()                     # draw the dashed one first, then the solid one
    ax.plot(T, np.cos(T), "--", color="black", lw=1)
    ax.plot(T, np.cos(T), **P.styled("increments/poly8_m6"))
    ax.legend(loc="center right")
    msg = one(P.check_figure(fig), "hidden under '8-node fit + Magnus-6'")
    assert "the dashed line (unlabelled, #000000)" in msg


def test_a_thin_dotted_line_under_an_identical_one_is_hidden():
    """Two documented-slope lines of coinciding series, drawn dotted at 1 pt on the same path:
    the first one's dots are all under the second's (its antialiased fringe is not seen)."""
    fig, ax = clean()
    for c in (P.colour("increments/miller3"), P.colour("increments/ignagni3")):
        ax.plot(T, np.sin(T) - 0.4, ":", color=c, lw=1)
    msg = one(P.check_figure(fig), "hidden under")
    assert "the dotted line (unlabelled, #875692)" in msg


# ------------------------------------------------------------------ legends over data

def test_a_legend_over_the_curves():
    fig, ax = clean()
    ax.legend(loc="center")                  # across both curves
    msg = one(P.check_figure(fig), "the legend covers data")
    assert "of its box over lines" in msg


def test_a_legend_beside_the_curves_passes():
    fig, ax = clean()
    ax.set_ylim(-1.1, 2.4)                    # room above the curves
    ax.legend(loc="upper right", ncols=2)
    assert P.check_figure(fig) == []
    fig, ax = clean()
    ax.get_legend().remove()
    fig.legend(loc="outside lower center", ncols=2)
    assert P.check_figure(fig) == []


def test_a_legend_over_one_marker():
    x = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    fig, ax = P.figure()
    ax.plot(x, [1.0, 1.5, 2.0, 2.5, 9.3], "o", ls="none", color=P.colour("BMI088"),
            label="BMI088")
    ax.set(xlabel="rate (Hz)", ylabel="error (m)", ylim=(0, 10))
    ax.legend(loc="upper right")             # over the last point, no line drawn at all
    msg = one(P.check_figure(fig), "the legend covers data")
    assert "1 marker under it" in msg
    ax.legend(loc="upper left")              # a corner without data
    assert P.check_figure(fig) == []


def test_a_figure_legend_placed_over_an_axes_counts_too():
    fig, ax = clean()
    ax.get_legend().remove()
    fig.legend(loc="center")
    one(P.check_figure(fig), "the figure legend covers data")


# ------------------------------------------------------------------ coinciding series

def _pixels_of(fig, colour):
    """How many pixels of the rendered figure have ``colour`` (within a few levels)."""
    import matplotlib.colors as mc

    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(int)
    want = np.array([round(255 * c) for c in mc.to_rgb(colour)])
    return int((np.abs(rgb - want).max(axis=-1) <= 6).sum())


def test_coinciding_series_are_one_striped_line_every_colour_visible():
    """Three series that coincide and one apart: one line made of the three colours in turn
    (equal widths: no halo), each series' markers beside the others', the check passes, and a
    legend entry names the three."""
    x = np.array([50.0, 100.0, 200.0, 400.0])
    same = ("increments/coning2", "increments/miller3", "increments/ignagni3")
    series = {i: 1e-2 * (x / 50) ** -2 for i in same}
    series["increments/first_order"] = 3e-2 * (x / 50) ** -2
    ids = [*same, "increments/first_order"]
    fig, ax = P.figure()
    drawn = P.plot_coinciding(ax, x, series, ids)
    ax.set(xscale="log", yscale="log", xlabel="sample rate (Hz)",
           ylabel="max position error (m)")
    assert drawn["groups"] == [list(same)]
    widths = {ln.get_linewidth() for ln in ax.lines if len(ln.get_xdata()) and
              ln.get_linestyle() != "None"}
    assert widths == {1.5}
    ax.legend(loc="lower left")
    assert P.check_figure(fig) == []
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "coincide: two-sample coning, Miller 3-sample, Ignagni 3-sample" in [
        " ".join(x.split()) for x in labels]                    # the label is wrapped
    assert {P.name(i) for i in ids} <= set(labels)
    fig.savefig(__import__("io").BytesIO())
    lone = _pixels_of(fig, P.colour("increments/first_order"))
    for i in same:                 # each stripe and marker set shows its colour
        assert _pixels_of(fig, P.colour(i)) > 0.2 * lone, i


def test_without_a_group_nothing_is_striped_or_noted():
    x = np.array([1.0, 2.0, 3.0])
    fig, ax = P.figure()
    drawn = P.plot_coinciding(ax, x, {"increments/coning2": x, "increments/miller3": 2 * x},
                              ["increments/coning2", "increments/miller3"])
    assert drawn["groups"] == [] and ax.get_legend() is None
    assert all(ln.get_linestyle() == "-" for ln in ax.lines)
