# One entry point: `make test` (what CI runs), `make check` (lint + format check), `make bench`.
.PHONY: test check bench

test:
	python -m pytest

check:
	ruff check src tests bench
	ruff format --check src tests bench

bench:
	python bench/lang.py
