//! No code: a dependency of every workspace crate that enables, on the
//! crates the engine is built from, the union of the features any build of
//! the workspace enables, so that `cargo build -p tumble-cli`, maturin's
//! build of `tumble-py` and `cargo test --workspace` all compile the engine
//! once, with the same features (cargo otherwise unifies features per
//! selection, and each selection compiled parquet, tumble-collide and tumble
//! again). Written by `cargo hakari generate` (.config/hakari.toml);
//! `scripts/check_feature_unification.py`, run by `make lint`, fails when it
//! falls behind the dependencies.
