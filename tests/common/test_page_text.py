"""Printed text fitted to the book's column (roughgp.common.page_text)."""

from roughgp.common import page_text


def test_long_lines_are_wrapped_and_short_ones_kept():
    text = "a short line\n" + " ".join(["word"] * 60) + "\n    indented " + "x " * 50
    fitted = page_text.fit_to_page(text)
    lines = fitted.splitlines()
    assert lines[0] == "a short line"
    assert all(len(line) <= page_text.PAGE_COLUMNS for line in lines)
    assert fitted.split() == text.split()          # nothing lost, nothing added
    assert any(line.startswith("      x") for line in lines)  # the indent kept, plus two


def test_a_word_longer_than_the_page_is_broken():
    assert all(len(line) <= 20 for line in page_text.fit_to_page("y" * 70, 20).splitlines())


def test_say_prints_like_print(capsys):
    page_text.say("Sq", 0.5, "µm")
    assert capsys.readouterr().out == "Sq 0.5 µm\n"


def test_the_book_writes_micrometres_as_its_figures_do(capsys):
    assert page_text.book_units("variance 0.9 um^2, lambda_a 87 um; psd um^4 (um)") == (
        "variance 0.9 µm², lambda_a 87 µm; psd µm⁴ (µm)")
    assert page_text.book_units("umbrella, sum, drum um3") == "umbrella, sum, drum um3"
    page_text.say("Sq 0.5 um")
    assert capsys.readouterr().out == "Sq 0.5 µm\n"
