"""notebooks/run.py writes a notebook back byte-stable from run to run (issue 25): its
normaliser drops the cells' execution timestamps and renames the random ipywidgets model ids by
order of first appearance, consistently in the views and in the stored widget state."""

import copy
import importlib.util
import json
import re
import uuid
from pathlib import Path

import nbformat
import pytest

spec = importlib.util.spec_from_file_location(
    "nb_run", Path(__file__).resolve().parents[2] / "notebooks" / "run.py")
run = importlib.util.module_from_spec(spec)
spec.loader.exec_module(run)

VIEW = "application/vnd.jupyter.widget-view+json"
STATE = "application/vnd.jupyter.widget-state+json"


def _model(name, **state):
    return {"model_module": "@jupyter-widgets/controls", "model_module_version": "2.0.0",
            "model_name": name, "state": {"_model_name": name, **state}}


def executed(seed: int, reverse: bool = False) -> dict:
    """A notebook as nbclient writes it: timestamps, and widget models with fresh uuids — a
    VBox of a slider and an Output widget (whose own outputs hold a nested widget view), each
    with its layout, and one model nothing refers to. ``reverse``: the models stored in the
    other order (the order comms were opened in is not the notebook's business)."""
    ids = [uuid.UUID(int=seed * 1000 + k).hex for k in range(7)]
    box, slider, output, lay_s, lay_o, inner, stray = ids
    stamp = {"iopub.execute_input": f"2026-12-02T00:{seed:02d}:16.562862Z",
             "shell.execute_reply": f"2026-12-02T00:{seed:02d}:17.665739Z"}
    state = {
        box: _model("VBoxModel", children=[f"IPY_MODEL_{slider}", f"IPY_MODEL_{output}"]),
        slider: _model("IntSliderModel", value=3, layout=f"IPY_MODEL_{lay_s}"),
        output: _model("OutputModel", layout=f"IPY_MODEL_{lay_o}", outputs=[
            {"output_type": "display_data", "metadata": {},
             "data": {"text/plain": "Label()", VIEW: {"model_id": inner, "version_major": 2,
                                                      "version_minor": 0}}},
            {"output_type": "stream", "name": "stdout", "text": "x = 3\n"}]),
        lay_s: _model("LayoutModel", width="460px"),
        lay_o: _model("LayoutModel", width=None),
        inner: _model("LabelModel", value="inner"),
        stray: _model("LayoutModel", width="1px"),
    }
    if reverse:
        state = dict(reversed(list(state.items())))
    cells = [
        {"cell_type": "markdown", "id": "m1", "metadata": {}, "source": "# A title"},
        {"cell_type": "code", "id": "c1", "execution_count": 1, "source": "print(1)",
         "metadata": {"tags": ["hide-input"], "execution": dict(stamp)},
         "outputs": [{"output_type": "stream", "name": "stdout", "text": "1\n"},
                     {"output_type": "display_data", "metadata": {"image/png": {"width": 3}},
                      "data": {"image/png": "iVBORw0KGgo=", "text/plain": "<Figure>"}}]},
        {"cell_type": "code", "id": "c2", "execution_count": 2, "source": "VBox(…)",
         "metadata": {"execution": dict(stamp)},
         "outputs": [{"output_type": "display_data", "metadata": {},
                      "data": {"text/plain": "VBox()", VIEW: {"model_id": box,
                                                              "version_major": 2,
                                                              "version_minor": 0}}}]},
    ]
    return nbformat.from_dict({
        "cells": cells, "nbformat": 4, "nbformat_minor": 5,
        "metadata": {"kernelspec": {"name": "python3", "display_name": "Python 3",
                                    "language": "python"},
                     "widgets": {STATE: {"state": state, "version_major": 2,
                                         "version_minor": 0}}}})


def written(nb, name="05_x") -> str:
    return nbformat.writes(run.normalise(nb, name))


def refs(nb) -> tuple[list[str], set[str]]:
    """(every model id that a view or a state refers to, the stored state's keys)."""
    text = json.dumps(nb)
    named = re.findall(r'"model_id": "([^"]+)"', text) + re.findall(r"IPY_MODEL_(\w+)", text)
    return named, set(nb.metadata.widgets[STATE]["state"])


def test_two_runs_that_differ_in_timestamps_and_ids_are_written_identical():
    a, b = executed(1), executed(2, reverse=True)
    assert nbformat.writes(a) != nbformat.writes(b)
    assert written(a) == written(b)


def test_timestamps_go_and_the_rest_of_the_cell_stays():
    nb = run.normalise(executed(1), "05_x")
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all("execution" not in c.metadata for c in code)
    assert code[0].metadata.tags == ["hide-input"]
    assert code[0].outputs == executed(1).cells[1].outputs      # text and figure untouched
    assert [c.source for c in nb.cells] == [c.source for c in executed(1).cells]


def test_every_id_is_renamed_consistently_in_views_and_state():
    raw = executed(1)
    old = set(raw.metadata.widgets[STATE]["state"])
    nb = run.normalise(copy.deepcopy(raw), "05_x")
    text = json.dumps(nb)
    assert not any(i in text for i in old), "an original uuid survived"
    named, keys = refs(nb)
    assert len(keys) == len(old) == 7
    assert set(named) <= keys, "a view or a reference names a model the state does not hold"
    assert all(re.fullmatch(r"[0-9a-f]{32}", k) for k in keys)
    # the first model met is the view in the cells' outputs; its children are numbered next
    view = nb.cells[2].outputs[0].data[VIEW]["model_id"]
    assert view == run._new_id("05_x", "widget", 0)
    box = nb.metadata.widgets[STATE]["state"][view]["state"]
    assert box["children"] == [f"IPY_MODEL_{run._new_id('05_x', 'widget', k)}" for k in (1, 2)]


def animation(seed: int) -> dict:
    """A notebook with matplotlib's jshtml animation output (its elements named by a fresh
    uuid4 on every call) twice, and an SVG with one."""
    a, b, c = (uuid.UUID(int=seed * 1000 + k, version=4).hex for k in range(3))
    html = (f'<img id="_anim_img{a}">\n<input id="_anim_slider{a}" '
            f'oninput="anim{a}.set_frame(parseInt(this.value));">\n'
            f'<script>var anim{a} = new Animation(frames, "_anim_img{a}");</script>')
    other = html.replace(a, b)
    svg = f'<svg><clipPath id="p{c}"/><g clip-path="url(#p{c})"/></svg>'
    outs = [{"output_type": "display_data", "metadata": {},
             "data": {"text/html": t, "text/plain": "<HTML>"}} for t in (html, other)]
    outs.append({"output_type": "display_data", "metadata": {},
                 "data": {"image/svg+xml": svg, "text/plain": "<Figure>"}})
    return nbformat.from_dict({
        "cells": [{"cell_type": "code", "id": "c1", "execution_count": 1, "source": "HTML(…)",
                   "metadata": {}, "outputs": outs}],
        "metadata": {}, "nbformat": 4, "nbformat_minor": 5})


def test_the_random_element_ids_of_html_and_svg_outputs_are_renamed_consistently():
    a, b = animation(1), animation(2)
    assert nbformat.writes(a) != nbformat.writes(b)
    once = written(a, "04_x")
    assert once == written(b, "04_x")
    assert written(nbformat.reads(once, as_version=4), "04_x") == once
    outs = nbformat.reads(once, as_version=4).cells[0].outputs
    first, second = (run._new_id("04_x", "markup", k) for k in (0, 1))
    assert outs[0].data["text/html"] == animation(1).cells[0].outputs[0].data["text/html"].replace(
        uuid.UUID(int=1000, version=4).hex, first)
    assert first not in outs[1].data["text/html"] and second in outs[1].data["text/html"]
    assert outs[2].data["image/svg+xml"].count(run._new_id("04_x", "markup", 2)) == 2


def test_a_stream_cut_in_pieces_is_stored_whole():
    """The kernel flushes stdout when its thread wakes: '27.64 h' and its newline came as two
    outputs on one run of notebook 09, as one on the other."""
    nb = executed(1)
    whole = copy.deepcopy(nb)
    nb.cells[1].outputs[0:1] = [nbformat.from_dict({"output_type": "stream", "name": "stdout",
                                                    "text": t}) for t in ("1", "\n")]
    nb.cells[1].outputs.insert(0, nbformat.from_dict({"output_type": "stream", "name": "stderr",
                                                      "text": "warning: w\n"}))
    whole.cells[1].outputs.insert(0, copy.deepcopy(nb.cells[1].outputs[0]))
    out = nb.metadata.widgets[STATE]["state"][uuid.UUID(int=1002).hex]["state"]["outputs"]
    out[1:2] = [{"output_type": "stream", "name": "stdout", "text": t} for t in ("x = ", "3\n")]
    assert written(nb) == written(whole)
    streams = [o for o in run.normalise(nb, "05_x").cells[1].outputs]
    assert [(o.get("name"), o.get("text")) for o in streams] == [
        ("stderr", "warning: w\n"), ("stdout", "1\n"), (None, None)]   # stderr stays apart


def test_ids_differ_between_notebooks():
    _, a = refs(run.normalise(executed(1), "03_a"))
    _, b = refs(run.normalise(executed(1), "05_b"))
    assert not a & b


def test_idempotent_also_through_the_file():
    once = written(executed(3, reverse=True))
    assert written(nbformat.reads(once, as_version=4)) == once


def test_a_notebook_without_widgets_only_loses_its_timestamps():
    nb = executed(1)
    del nb.metadata["widgets"]
    nb.cells = nb.cells[:2]
    out = run.normalise(copy.deepcopy(nb), "00_x")
    assert "execution" not in out.cells[1].metadata
    del nb.cells[1].metadata["execution"]
    assert out == nb


def test_run_one_twice_writes_the_same_bytes(tmp_path):
    """The runner itself, on a small notebook with a printed line, a figure and a widget: the
    file written by the second run is the first run's, byte for byte."""
    pytest.importorskip("ipywidgets")
    src = ("import matplotlib.pyplot as plt\nfig, ax = plt.subplots(figsize=(3, 2), dpi=150)\n"
           "ax.plot([0, 1], [0, 1], label='a line')\nax.set(xlabel='t (s)', ylabel='x (m)')\n"
           "ax.legend()\nplt.show()")
    widget = ("from ipywidgets import IntSlider, interactive_output, VBox\n"
              "s = IntSlider(value=3, description='n', continuous_update=False)\n"
              "VBox([s, interactive_output(lambda n: print(n * n), {'n': s})])")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("print(2 + 2)"),
                                         nbformat.v4.new_code_cell(src),
                                         nbformat.v4.new_code_cell(widget)])
    path = tmp_path / "99_tiny.ipynb"
    nbformat.write(nb, path)
    texts = []
    for _ in range(2):
        ok, _lost = run.run_one(path, timeout=120, sync=False, check="warn")
        assert ok
        texts.append(path.read_bytes())
    assert texts[0] == texts[1]
    stored = nbformat.reads(texts[0].decode(), as_version=4)
    assert stored.metadata.widgets[STATE]["state"], "the widget state is stored"
    assert all("execution" not in c.metadata for c in stored.cells)
