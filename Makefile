# tumble: the two commands of the README, and the pieces they are made of.
#   make demo   runs the demo simulation and writes its outputs to out/
#   make test   runs every test (this is what .ci/run calls)

CARGO ?= cargo
export CARGO_TERM_COLOR ?= never

.PHONY: demo test lint fmt-check clippy rust-test viewer-test bench

demo:
	$(CARGO) run --release -p tumble-cli -- demo --out out

test: lint rust-test viewer-test

lint: fmt-check clippy

fmt-check:
	$(CARGO) fmt --all -- --check

clippy:
	$(CARGO) clippy --workspace --all-targets -- -D warnings

rust-test:
	$(CARGO) test --workspace --release

# Builds the web viewer and checks it in headless Chromium (installs chromium
# and the npm packages on first use, see viewer/scripts/setup.sh).
viewer-test:
	bash viewer/scripts/setup.sh
	bash viewer/scripts/test.sh

bench:
	$(CARGO) bench --workspace
