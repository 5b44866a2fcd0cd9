//! Checks of loaded parameters. Each parameter type validates itself beside its definition
//! ([`Validate`]), into one [`Checks`] that keeps the first failure as a sentence naming the
//! key, the value and what is allowed; the scene adds the checks that span several tables.
//! Here too: what a scene's input may hold at most, and the error it gets ([`SceneError`]).

/// The most blades one field may hold (2^26: 4 GiB of blades would be the next step).
pub const MAX_BLADES: u32 = 1 << 26;

/// The largest number a scene may hold anywhere (units, seconds, strengths): beyond it, float
/// arithmetic on the GPU (a view matrix of a camera 1e30 units away) overflows to infinity.
pub const MAX_MAGNITUDE: f64 = 1e6;

/// What is wrong with a scene file.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The text is not a scene file: bad TOML, an unknown key, a value of the wrong type.
    #[error("{origin}: line {line}, column {column}: {message}")]
    Syntax {
        /// Where the text came from (a file name).
        origin: String,
        /// Line of the mistake, from 1.
        line: usize,
        /// Column of the mistake, from 1.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A `--set` key the scene file does not have.
    #[error("--set {key}: the scene file has no such key; {hint}")]
    UnknownKey {
        /// The key given.
        key: String,
        /// The nearest key the scene has ("did you mean wind.strength?"), or what keys look
        /// like where none is near.
        hint: String,
    },
    /// A `--set` value that does not fit its key.
    #[error("--set {key}={value}: {message}")]
    BadOverride {
        /// The key.
        key: String,
        /// The value given.
        value: String,
        /// What is wrong.
        message: String,
    },
    /// An array longer than its key takes.
    #[error("{origin}: {key} has {written} values; it takes {takes}")]
    TooManyValues {
        /// Where the scene came from.
        origin: String,
        /// The key.
        key: String,
        /// Values written.
        written: usize,
        /// Values it takes.
        takes: usize,
    },
    /// A number that is not finite or of absurd size.
    #[error("{origin}: {key} = {value} is not allowed: every number in a scene is finite and within ±{MAX_MAGNITUDE}")]
    Absurd {
        /// Where the scene came from.
        origin: String,
        /// The key.
        key: String,
        /// The value written.
        value: String,
    },
    /// A value outside what its key allows.
    #[error("{origin}: {key} = {value} is not allowed: {allowed}")]
    Invalid {
        /// Where the scene came from.
        origin: String,
        /// The key.
        key: String,
        /// The value written.
        value: String,
        /// What is allowed.
        allowed: std::borrow::Cow<'static, str>,
    },
}

/// A parameter type that checks its own values.
pub(crate) trait Validate {
    /// Check every value, under the scene file's keys.
    fn validate(&self, c: &mut Checks);
}

/// Collects the first failed check of a scene.
pub(crate) struct Checks<'a> {
    origin: &'a str,
    error: Option<SceneError>,
    /// Where recording: every key checked and what it allows, passed or not.
    record: Option<Vec<(String, std::borrow::Cow<'static, str>)>>,
}

impl<'a> Checks<'a> {
    /// Checks of the scene from `origin` (a file name, in messages).
    pub fn new(origin: &'a str) -> Checks<'a> {
        Checks {
            origin,
            error: None,
            record: None,
        }
    }

    /// Checks that also record what each key checked allows ([`Checks::allowed`]).
    pub fn recording(origin: &'a str) -> Checks<'a> {
        Checks {
            record: Some(Vec::new()),
            ..Checks::new(origin)
        }
    }

    /// What the first check of `key` said it allows, where the checks were recording.
    pub fn allowed(&self, key: &str) -> Option<std::borrow::Cow<'static, str>> {
        let record = self.record.as_ref()?;
        record
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, allowed)| allowed.clone())
    }

    /// The first failure, if any.
    pub fn finish(self) -> Result<(), SceneError> {
        self.error.map_or(Ok(()), Err)
    }

    /// Whether every check so far passed.
    pub fn passed(&self) -> bool {
        self.error.is_none()
    }

    /// Fail with `key = value`, saying what is `allowed`, unless `ok`.
    pub fn check(
        &mut self,
        ok: bool,
        key: impl Into<String>,
        value: impl std::fmt::Debug,
        allowed: impl Into<std::borrow::Cow<'static, str>>,
    ) {
        if (ok || self.error.is_some()) && self.record.is_none() {
            return;
        }
        let (key, allowed) = (key.into(), allowed.into());
        if let Some(record) = &mut self.record {
            record.push((key.clone(), allowed.clone()));
        }
        if !ok && self.error.is_none() {
            let value = format!("{value:?}").trim_matches('"').to_string();
            self.error = Some(SceneError::Invalid {
                origin: self.origin.into(),
                key,
                value,
                allowed,
            });
        }
    }

    /// A `[min, max]` range with 0 < min ≤ max.
    pub fn range(&mut self, key: impl Into<String>, r: [f32; 2]) {
        let ok = r[0] > 0.0 && r[0] <= r[1] && r[1].is_finite();
        let shown = format!("[{}, {}]", r[0], r[1]);
        self.check(ok, key, shown, "a range [min, max] with 0 < min ≤ max");
    }

    /// A finite value ≥ 0.
    pub fn non_negative(&mut self, key: impl Into<String>, v: f32) {
        self.check(finite_non_negative(v), key, v, "a finite value ≥ 0");
    }
}

/// Finite and ≥ 0.
pub(crate) fn finite_non_negative(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}
