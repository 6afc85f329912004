//! The rigid motion taking one scan's crest lines onto another's (`crestline
//! register`; trimmed ICP, Chetverikov et al. 2002).

use crate::progress::{checkpoint, stage, Observer};
use crate::register::{register as align, PointSet, Registration, RegistrationOptions};
use crate::Result;

/// The rigid motion taking `moving` onto `fixed` as `options` say
/// ([`crate::register::register`]): the stage `registration`, and the counts
/// `fixed_points`, `moving_points` and `matched`.
pub fn register(
    fixed: &PointSet,
    moving: &PointSet,
    options: &RegistrationOptions,
    observer: &mut dyn Observer,
) -> Result<Registration> {
    options.validate()?;
    // Too few points is the caller's argument, not a failure of the stage.
    checkpoint(observer)?;
    let found = stage(observer, "registration", || align(fixed, moving, options))?;
    observer.count("fixed_points", fixed.line_points.len());
    observer.count("moving_points", moving.line_points.len());
    observer.count("matched", found.matched);
    Ok(found)
}
