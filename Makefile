# tumble: the two commands of the README, and the pieces they are made of.
#   make demo   runs the demo simulation and writes its outputs to out/
#   make test   runs every test (this is what .ci/run calls)

CARGO ?= cargo
export CARGO_TERM_COLOR ?= never

.PHONY: demo test lint fmt-check clippy rust-test bench

demo:
	$(CARGO) run --release -p tumble-cli -- demo --out out

test: lint rust-test

lint: fmt-check clippy

fmt-check:
	$(CARGO) fmt --all -- --check

clippy:
	$(CARGO) clippy --workspace --all-targets -- -D warnings

rust-test:
	$(CARGO) test --workspace --release

bench:
	$(CARGO) bench --workspace
