# One entry point: `make test` (what CI runs), `make check` (ruff lint + format check;
# pip install -e '.[dev]'), `make bench` (all benchmarks, a few seconds each), `make docs`
# (the documentation site into site/; pip install -e '.[docs]').
.PHONY: test check bench docs

test:
	python -m pytest

check:
	ruff check src tests bench
	ruff format --check src tests bench

bench:
	python bench/lang.py
	python bench/motion.py
	python bench/pdl.py

docs:
	mkdocs build --strict
