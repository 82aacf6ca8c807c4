# PatternBridge — `make demo` and `make test` are the quick start.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
DEMO_CHARACTER := examples/characters/E_average_male.obj
DEMO_GARMENT   := shirt
DEMO_OUT       := out/demo

.PHONY: demo test lint bench system-deps browser-deps clean help

help:
	@echo "make demo   create .venv, install, fit the $(DEMO_GARMENT) to the demo character"
	@echo "make test   create .venv, install with the test extra, lint, run the test suite"
	@echo "make lint   ruff over the package, tests, benchmarks and garment drafts"
	@echo "make bench  run the benchmarks (installs the bench extra)"

# open3d's wheel links against libusb-1.0 (Debian package libusb-1.0-0).
system-deps:
	@if ! /sbin/ldconfig -p 2>/dev/null | grep -q 'libusb-1.0.so.0'; then \
	  if [ "$$(id -u)" = "0" ] && command -v apt-get >/dev/null; then \
	    echo "installing libusb-1.0-0 (needed by open3d)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libusb-1.0-0 >/dev/null; \
	  else \
	    echo "open3d needs the system library libusb-1.0; run: sudo apt-get install libusb-1.0-0"; exit 1; \
	  fi; \
	fi

# The browser test of the batch page drives Debian's chromium through Playwright (never a downloaded browser).
browser-deps:
	@if [ ! -x /usr/bin/chromium ]; then \
	  if [ "$$(id -u)" = "0" ] && command -v apt-get >/dev/null; then \
	    echo "installing chromium (the browser test of the batch page)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; \
	  else \
	    echo "note: /usr/bin/chromium is missing, the browser test will be skipped (sudo apt-get install chromium)"; \
	  fi; \
	fi

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	@touch $@

$(VENV)/.installed-test: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test]"
	@touch $@ $(VENV)/.installed

$(VENV)/.installed-bench: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test,bench]"
	@touch $@ $(VENV)/.installed $(VENV)/.installed-test

# The Khronos glTF validator the export tests run (they skip it when node is absent).
GLTF_VALIDATOR := tests/tools/node_modules/.installed
$(GLTF_VALIDATOR): tests/tools/package.json tests/tools/package-lock.json
	@if command -v npm >/dev/null; then \
	  npm ci --prefix tests/tools --no-audit --no-fund --silent && touch $@; \
	else \
	  echo "npm not found: the glTF validator test will be skipped"; \
	fi

# fit exits 3 when the drape's verdict is "failed" (the files are written all the same): the demo shows the
# verdict and where to look rather than stopping there.
demo: system-deps $(VENV)/.installed
	@$(BIN)/patternbridge fit $(DEMO_CHARACTER) --garment $(DEMO_GARMENT) --seed 1 -o $(DEMO_OUT); \
	  status=$$?; [ $$status -eq 0 ] || [ $$status -eq 3 ] || exit $$status
	@echo
	@echo "Demo outputs are in $(DEMO_OUT)/ (the drape's verdict and its reasons: fit_report.json, under \"drape\"):"
	@ls -1 $(DEMO_OUT) | sed 's/^/  /'

test: system-deps browser-deps $(VENV)/.installed-test $(GLTF_VALIDATOR)
	$(BIN)/ruff check patternbridge tests benchmarks garment_library
	$(BIN)/python -m pytest -q -p no:cacheprovider

lint: $(VENV)/.installed-test
	$(BIN)/ruff check patternbridge tests benchmarks garment_library

bench: system-deps $(VENV)/.installed-bench
	@for script in benchmarks/*.py; do echo "== $$script"; $(BIN)/python $$script || exit 1; done

clean:
	rm -rf $(VENV) out .pytest_cache
