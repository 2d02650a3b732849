"""The column check of executed notebooks (booktools/page_fit.py): it says no to a figure with
small text (shrunk or not), to an unmeasured wide figure and to a long printed line, and yes to
what fits;
the kernel records each shown figure's width and smallest text (plotting.use_style)."""

import nbformat
import pytest

from booktools import page_fit
from roughgp.common import plotting, shown_figures

# a 1 x 1 px PNG's signature and header, with the width patched in
_PNG_HEAD = bytes.fromhex("89504e470d0a1a0a0000000d49484452")


def _png(width):
    import base64

    return base64.b64encode(_PNG_HEAD + width.to_bytes(4, "big") + (1).to_bytes(4, "big")
                            + b"\x08\x06\x00\x00\x00").decode()


def _figure_output(width, smallest=None, recorded=True):
    metadata = {"image/png": {shown_figures.SHOWN_KEY: {"width_px": width,
                                                   "smallest_text_pt": smallest}}}
    return nbformat.v4.new_output("display_data", data={"image/png": _png(width)},
                                  metadata=metadata if recorded else {})


def _notebook(*outputs, tags=()):
    cell = nbformat.v4.new_code_cell("x")
    cell.outputs = list(outputs)
    cell.metadata["tags"] = list(tags)
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("text"), nbformat.v4.new_code_cell("y"), cell]
    return nb


def test_png_width_reads_the_header():
    assert shown_figures.png_width(_png(1002)) == 1002


@pytest.mark.parametrize("output, fits", [
    (_figure_output(680, smallest=9.2), True),           # not shrunk, text >= 9 pt
    (_figure_output(680, smallest=8.0), False),          # not shrunk, but a 7 pt legend
    (_figure_output(680, recorded=False), True),         # not shrunk, not drawn in the style
    (_figure_output(900, smallest=9.4), True),           # shrunk, text still >= 9 pt
    (_figure_output(1002, smallest=8.6), False),         # shrunk below 9 pt
    (_figure_output(1002, recorded=False), False),       # cannot be measured
    (nbformat.v4.new_output("stream", text="a" * 81 + "\n"), True),
    (nbformat.v4.new_output("stream", text="ok\n" + "a" * 82 + "\n"), False),
    (nbformat.v4.new_output("stream", name="stderr", text="a" * 120), True),  # not shown
    (nbformat.v4.new_output("execute_result", data={"text/plain": "b" * 120}), False),
    (nbformat.v4.new_output("execute_result", data={"text/plain": "b" * 120,
                                                    "text/html": "<table></table>"}), True),
])
def test_overflow_says_no_only_to_what_does_not_fit(output, fits):
    problems = page_fit.overflow(_notebook(output))
    assert (problems == []) is fits, problems
    if not fits:
        assert problems[0].startswith("code cell 2: ")


def test_hidden_outputs_are_not_read_but_their_figures_are():
    long_line = nbformat.v4.new_output("stream", text="c" * 200)
    assert page_fit.overflow(_notebook(long_line, tags=["remove-output"])) == []
    wide = _figure_output(1200, smallest=7.0)
    assert len(page_fit.overflow(_notebook(wide, tags=["remove-cell"]))) == 1


def test_a_kernel_records_the_figures_it_shows(tmp_path):
    """A real kernel: after use_style, a 10 in figure is recorded shrunk (text under 9 pt), a
    6 in one not; the check fails the first only."""
    from nbclient import NotebookClient

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(
        "import matplotlib.pyplot as plt\n"
        "from roughgp.common import plotting\n"
        "plotting.use_style()"),
        nbformat.v4.new_code_cell(
            "fig, ax = plt.subplots(figsize=(10, 3)); ax.plot([0, 1]); ax.set_xlabel('x (µm)')"),
        nbformat.v4.new_code_cell(
            "fig, ax = plt.subplots(figsize=(6, 3)); ax.plot([0, 1]); ax.set_xlabel('x (µm)')")]
    NotebookClient(nb, kernel_name="python3", timeout=120, resources={
        "metadata": {"path": str(tmp_path)}}).execute()
    records = [o["metadata"]["image/png"][shown_figures.SHOWN_KEY] for cell in nb.cells[1:]
               for o in cell.outputs if "image/png" in o.get("data", {})]
    assert len(records) == 2
    wide, narrow = records
    assert wide["width_px"] > plotting.PAGE_WIDTH_PX > narrow["width_px"]
    assert wide["smallest_text_pt"] < plotting.MIN_FONT_PT <= narrow["smallest_text_pt"]
    problems = page_fit.overflow(nb)
    assert len(problems) == 1 and problems[0].startswith("code cell 2: a figure")


def test_a_figure_shown_from_a_file_carries_its_text_size(tmp_path):
    """save_for_page writes the smallest text's size into the PNG; the check reads it there when
    the chapter shows the file (the claims ledger's figures)."""
    import base64

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plotting.use_style()
    sizes = {}
    for width in (6.0, 10.0):
        fig, ax = plt.subplots(figsize=(width, 3))
        ax.plot([0, 1], label="a line")
        ax.legend()
        path = tmp_path / f"{width}.png"
        sizes[width] = shown_figures.save_for_page(fig, path, dpi=110)
        plt.close(fig)
        data = base64.b64encode(path.read_bytes()).decode()
        assert float(shown_figures.png_text(data)[shown_figures.PNG_TEXT_KEY]) == pytest.approx(
            sizes[width], abs=0.01)
        output = nbformat.v4.new_output("display_data", data={"image/png": data})
        problems = page_fit.overflow(_notebook(output))
        assert (problems == []) is (width == 6.0), problems
    assert sizes[6.0] == pytest.approx(10 * 110 / 72 * 0.75)     # the 10 pt legend, not shrunk
    assert sizes[10.0] < plotting.MIN_FONT_PT
