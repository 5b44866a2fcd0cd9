//! Checks of loaded parameters. Each parameter type validates itself beside its definition
//! ([`Validate`]), into one [`Checks`] that keeps the first failure as a sentence naming the
//! key, the value and what is allowed; the scene adds the checks that span several tables.

use crate::scene::SceneError;

/// A parameter type that checks its own values.
pub(crate) trait Validate {
    /// Check every value, under the scene file's keys.
    fn validate(&self, c: &mut Checks);
}

/// Collects the first failed check of a scene.
pub(crate) struct Checks<'a> {
    origin: &'a str,
    error: Option<SceneError>,
}

impl<'a> Checks<'a> {
    /// Checks of the scene from `origin` (a file name, in messages).
    pub fn new(origin: &'a str) -> Checks<'a> {
        Checks { origin, error: None }
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
    pub fn check(&mut self, ok: bool, key: impl Into<String>, value: impl std::fmt::Debug, allowed: &'static str) {
        if !ok && self.error.is_none() {
            let value = format!("{value:?}").trim_matches('"').to_string();
            self.error = Some(SceneError::Invalid {
                origin: self.origin.into(),
                key: key.into(),
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
