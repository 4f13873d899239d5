# Lanterna — the two commands of a fresh machine are `make demo` and `make test`.
# Both install whatever is missing first (a Python venv, npm packages, the plugin build).

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PORT   ?= 8000
CHROMIUM := /usr/bin/chromium
DEMO_TOKEN := .demo-token
PLUGIN_SOURCES := $(shell find plugin/src plugin/*.html plugin/*.ts plugin/*.json -type f 2>/dev/null)

.PHONY: demo test install build wheel lint typecheck typecheck-tree test-unit test-python browser-deps serve clean screenshot

demo: install build $(DEMO_TOKEN) ## make the demo dataset, serve it (authoring on) and print the URL
	@echo "Authoring token of this demo (the viewer asks for it when you save presets or upload annotations): $$(cat $(DEMO_TOKEN))"
	$(VENV)/bin/lanterna demo --root datasets --port $(PORT) --authoring-token-file $(DEMO_TOKEN)

# The demo's authoring token: made once, private to you (the server reads it from this file, never
# from the command line).
$(DEMO_TOKEN):
	umask 077 && $(PYTHON) -c 'import secrets; print(secrets.token_urlsafe(24))' > $@

test: install build browser-deps lint typecheck test-unit test-python ## run every test

install: $(VENV)/.installed node_modules/.installed

$(VENV)/.installed: pyproject.toml setup.py
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@

node_modules/.installed: package.json package-lock.json plugin/package.json
	npm ci --no-audit --no-fund
	touch $@

build: plugin/dist/.built

plugin/dist/.built: node_modules/.installed $(PLUGIN_SOURCES)
	npm run build
	touch $@

wheel: install build ## dist/lanterna-VERSION-py3-none-any.whl, with the built viewer inside
	$(PY) -m pip wheel --quiet --no-deps --no-build-isolation -w dist .

browser-deps:
	@test -x $(CHROMIUM) || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; \
	  else echo "Browser tests need Debian's Chromium: sudo apt-get install -y chromium"; exit 1; fi; }

lint: install
	$(VENV)/bin/ruff check lanterna tiler manifests server tests tools
	npm run lint

typecheck: install typecheck-tree
	$(VENV)/bin/mypy
	npm run typecheck

# mypy sees the package as installed: lanterna/ with tiler/, manifests/, server/ linked inside it
typecheck-tree:
	@rm -rf .typecheck && mkdir -p .typecheck/lanterna
	@for f in lanterna/*; do ln -s "$$PWD/$$f" .typecheck/lanterna/; done
	@for d in tiler manifests server; do ln -s "$$PWD/$$d" .typecheck/lanterna/$$d; done

test-unit: install
	npm run test:unit

test-python: install build
	$(VENV)/bin/pytest

screenshot: install build ## retake the README screenshots (docs/screenshot*.png) from the demo dataset
	$(PY) tools/screenshot.py --root datasets --out-dir docs

clean:
	rm -rf plugin/dist datasets tests/browser/out build dist
