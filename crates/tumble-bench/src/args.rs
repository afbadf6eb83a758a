//! Minimal command-line parsing shared by the peer binaries: `--scene S`, `--steps K`,
//! `--n N`, `--poses P`. Errors are typed; nothing panics on user input.

use thiserror::Error;

/// A bad command line.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum ArgError {
    /// A flag that this binary does not know.
    #[error("unknown argument `{0}`; expected --scene, --steps, --n or --poses")]
    Unknown(String),
    /// A flag given without its value.
    #[error("`{0}` needs a value")]
    MissingValue(String),
    /// A value that is not a positive integer.
    #[error("`{flag}` expects a positive integer, got `{value}`")]
    NotPositive {
        /// The flag.
        flag: String,
        /// What was given.
        value: String,
    },
}

/// Parsed arguments; `None` means "the scene's default".
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Args {
    /// Scene name (`pyramid`, `pile`, `tori`).
    pub scene: Option<String>,
    /// Number of steps (overrides the scene's 600).
    pub steps: Option<usize>,
    /// Pile body count (multiple of 100).
    pub n: Option<usize>,
    /// Tori: number of poses, spread evenly over the 200.
    pub poses: Option<usize>,
    /// Worker threads (Rapier's `parallel` feature runs on this many).
    pub threads: Option<usize>,
}

impl Args {
    /// Parses `argv` without the program name.
    pub fn parse<I: IntoIterator<Item = String>>(argv: I) -> Result<Args, ArgError> {
        let mut out = Args::default();
        let mut it = argv.into_iter();
        while let Some(flag) = it.next() {
            let value = match flag.as_str() {
                "--scene" | "--steps" | "--n" | "--poses" | "--threads" => {
                    it.next().ok_or_else(|| ArgError::MissingValue(flag.clone()))?
                }
                _ => return Err(ArgError::Unknown(flag)),
            };
            if flag == "--scene" {
                out.scene = Some(value);
                continue;
            }
            let n: usize = value
                .parse()
                .ok()
                .filter(|&n| n > 0)
                .ok_or_else(|| ArgError::NotPositive {
                    flag: flag.clone(),
                    value: value.clone(),
                })?;
            match flag.as_str() {
                "--steps" => out.steps = Some(n),
                "--n" => out.n = Some(n),
                "--threads" => out.threads = Some(n),
                _ => out.poses = Some(n),
            }
        }
        Ok(out)
    }

    /// This process's arguments, or, on a bad command line, the peers' protocol:
    /// one line `{program}: {error}` on stderr and exit status 2.
    pub fn from_env_or_exit(program: &str) -> Args {
        match Args::parse(std::env::args().skip(1)) {
            Ok(a) => a,
            Err(e) => {
                eprintln!("{program}: {e}");
                std::process::exit(2);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<Args, ArgError> {
        Args::parse(s.split_whitespace().map(String::from))
    }

    #[test]
    fn parses_all_flags_and_rejects_bad_values() {
        let a = parse("--scene pile --n 1000 --steps 5").unwrap();
        assert_eq!(a.scene.as_deref(), Some("pile"));
        assert_eq!((a.n, a.steps, a.poses), (Some(1000), Some(5), None));
        assert_eq!(
            parse("--steps 0"),
            Err(ArgError::NotPositive {
                flag: "--steps".into(),
                value: "0".into()
            })
        );
        assert_eq!(parse("--n"), Err(ArgError::MissingValue("--n".into())));
        assert_eq!(parse("--x 1"), Err(ArgError::Unknown("--x".into())));
    }
}
