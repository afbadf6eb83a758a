# tumble: the two commands of the README, and the pieces they are made of.
#   make demo   runs the demo simulation and writes its outputs to out/
#   make test   runs every test (this is what .ci/run calls)

CARGO ?= cargo
export CARGO_TERM_COLOR ?= never

.PHONY: demo test lint fmt-check clippy feature-check rust-test doc viewer-test bench-quick bench python-env python-test python-bench manual manual-test soak fuzz

# The torus demo first (two tori through exact mesh-mesh contact, then the
# 21-link torus chain), then domino and Dzhanibekov; finally the web viewer
# that `tumble view` serves (npm only, no browser install).
TUMBLE := target/release/tumble
demo:
	$(CARGO) build --release -p tumble-cli
	$(TUMBLE) run examples/scenes/tori_pass.toml --out out/tori_pass.glb --trajectory out/tori_pass.csv
	$(TUMBLE) run examples/scenes/chain.toml --out out/chain.glb --trajectory out/chain.npz
	$(TUMBLE) demo --out out --quiet
	VIEWER_SETUP_NO_BROWSER=1 bash viewer/scripts/setup.sh
	cd viewer && npm run build --silent
	@echo
	@echo "watch the demo:  $(TUMBLE) view out/tori_pass.glb   (or out/chain.glb, out/domino.glb)"
	@echo "live:            $(TUMBLE) view examples/scenes/tori_pass.toml"

test: lint rust-test doc viewer-test bench-quick python-test manual-test

lint: fmt-check clippy feature-check

fmt-check:
	$(CARGO) fmt --all -- --check

clippy:
	$(CARGO) clippy --workspace --all-targets -- -D warnings

# Every cargo build below (and maturin's) must compile the engine with the
# workspace's dependency features, or each compiles it again
# (crates/tumble-workspace-hack; seconds, no build).
feature-check:
	python3 scripts/check_feature_unification.py

rust-test:
	$(CARGO) test --workspace --release

# API docs with every rustdoc warning an error (missing docs, broken or
# ambiguous intra-doc links), the private items' docs checked first; then
# the public docs, target/doc/tumble/index.html. Reuses clippy's dependency
# builds, so it takes seconds after `make clippy`.
doc:
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --workspace --no-deps --document-private-items
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --workspace --no-deps

# Builds the web viewer and checks it in headless Chromium (installs chromium
# and the npm packages on first use, see viewer/scripts/setup.sh).
viewer-test:
	bash viewer/scripts/setup.sh
	bash viewer/scripts/test.sh

# The side-by-side benchmark harness in its quick mode (a few steps per scene),
# so that it cannot rot (bench/run.py builds tumble and the Rust peers first); peers that are not installed are recorded, not failed;
# it fails when tumble errs or gives a wrong answer (tori pairs against the
# truth file, pyramid standing, pile contained).
# run.py --quick builds tumble-cli and tumble-bench (peers and the cores'
# round-trip probe), which the harness checks then use.
bench-quick:
	python3 bench/run.py --quick
	python3 -m unittest bench/test_common.py

bench:
	$(CARGO) bench --workspace

# The Python package: .venv with the pinned tools, `pip install .` of
# crates/tumble-py (see scripts/python-env.sh), then lint, tests and examples.
PYTHON_SOURCES = crates/tumble-py/python crates/tumble-py/tests examples/python bench/python_overhead.py \
	bench/python_query_overhead.py bench/rollout_overhead.py bench/peers bench/test_common.py scripts/manual_blocks.py \
	scripts/check_feature_unification.py

python-env:
	bash scripts/python-env.sh

# The scene and sweep tests compare with `tumble run` and `tumble sweep`, so
# the CLI is built first. test_sweep_ray.py starts a 2-CPU Ray cluster here.
python-test: python-env
	.venv/bin/ruff check $(PYTHON_SOURCES)
	$(CARGO) build --release -p tumble-cli
	.venv/bin/python -m pytest -q crates/tumble-py/tests
	bash scripts/python-examples.sh
	$(CARGO) build --release -p tumble --example step_readback
	.venv/bin/python bench/python_overhead.py --quick
	.venv/bin/python bench/python_query_overhead.py --quick
	$(CARGO) build --release -p tumble --example batch_rollout
	.venv/bin/python bench/rollout_overhead.py --quick

# Python-vs-Rust overhead of step() + pose readback for 1,000 bodies
# (bench/python_overhead.py; results in out/python_overhead.json), and of
# tumble.collide on the tori against `tumble bench --scene tori`
# (bench/python_query_overhead.py; out/python_query_overhead.json), and of
# tumble.rollout over the Rust batch on 1 and 2 threads
# (bench/rollout_overhead.py; out/rollout_overhead.json).
python-bench: python-env
	$(CARGO) build --release -p tumble --example step_readback
	$(CARGO) build --release -p tumble --example batch_rollout
	$(CARGO) build --release -p tumble-cli
	.venv/bin/python bench/python_overhead.py
	.venv/bin/python bench/python_query_overhead.py
	.venv/bin/python bench/rollout_overhead.py


# The user manual (docs/manual): its Rust blocks are doc-tests of
# crates/tumble-manual (run by rust-test); this runs the Python, TOML, JSON and
# `tumble` shell blocks (scripts/manual_blocks.py).
manual-test: python-env
	$(CARGO) build --release -p tumble-cli
	python3 scripts/manual_blocks.py

# The manual as HTML in target/manual/ (installs the pinned mdbook into
# target/tools on first use; see scripts/manual.sh).
manual:
	bash scripts/manual.sh

# Long runs, off the CI path: the pile(100) and the chain for 100,000 steps
# each (dt 1/240) with NaN, containment, energy and memory checks and a
# printed summary (crates/tumble/tests/soak.rs; shorter versions run in
# `make test`).
soak:
	$(CARGO) test --release -p tumble --test soak -- --ignored --nocapture --test-threads=1

# libFuzzer on every target for FUZZ_SECONDS each (nightly + cargo-fuzz,
# installed by the script); `make test` runs the same targets on stable in
# seconds (crates/tumble/tests/fuzz_smoke.rs).
FUZZ_SECONDS ?= 60
fuzz:
	bash scripts/fuzz.sh $(FUZZ_SECONDS)
