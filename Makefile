# The two set-up commands of the README: `make book` and `make test`.
# Each creates ./.venv on first use (torch==2.13.0 first, then the lock, then roughgp).
# `make test` runs the unit tests and, with nbmake, every chapter (book/) and lab (notebooks/).
# Both execute the notebooks through one cache (book/_build/.jupyter_cache, see
# booktools/notebook_cache.py): whichever runs second reuses what the first executed.
# `make student` writes the labs without their solutions (book/_build/student/: the notebooks, a
# zip, and the book built without solutions, from the same cache), and beside them the lecturer's
# key (book/_build/lecturer/key.md: the reference solutions and the model answers).
# `make pdf` prints the book as one PDF (book/_build/pdf/book.pdf) with the system's Chromium.
PYTHON ?= python3.11
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.roughgp-installed

# Test processes side by side (the notebooks run two at a time on the 2-core reference machine).
JOBS ?= 2

.PHONY: install book test student pdf clean

$(STAMP): requirements.lock pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet torch==2.13.0
	$(BIN)/python -m pip install --quiet -r requirements.lock
	$(BIN)/python -m pip install --quiet --no-deps --no-build-isolation -e .
	$(BIN)/python -m pip check
	touch $(STAMP)

install: $(STAMP)

book: $(STAMP)
	$(BIN)/jupyter-book build -W -n --keep-going book/
	@echo "book: open book/_build/html/index.html"

test: $(STAMP)
	$(BIN)/python -m pytest --nbmake -n $(JOBS) --dist worksteal

student: $(STAMP)
	$(BIN)/python -m booktools.student

pdf: $(STAMP)
	$(BIN)/python -m booktools.pdf

clean:
	rm -rf book/_build
