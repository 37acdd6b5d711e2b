//! What the panel says of a still view's samples: how many the path
//! tracer (or the anti-aliasing) has averaged, out of how many, and for
//! how long ([`SampleClock`]).

use std::time::Duration;

/// The time a still view has spent gathering its samples: it starts
/// again when the count falls (the view moved, so the pass started over)
/// and stops when every sample is in.
#[derive(Clone, Debug, Default)]
pub struct SampleClock {
    last: u32,
    spent: Duration,
    done: bool,
}

impl SampleClock {
    /// Takes the count drawn this frame (`samples` of `wanted`) and the
    /// time since the last frame; returns the time spent on this view's
    /// samples so far.
    pub fn tick(&mut self, samples: u32, wanted: u32, frame: Duration) -> Duration {
        if samples < self.last || samples <= 1 {
            self.spent = Duration::ZERO;
            self.done = false;
        } else if !self.done {
            self.spent += frame;
        }
        self.done = samples >= wanted;
        self.last = samples;
        self.spent
    }

    /// The panel's line: `12 of 256 samples, 3.4 s`.
    #[must_use]
    pub fn line(samples: u32, wanted: u32, spent: Duration) -> String {
        format!("{samples} of {wanted} samples, {:.1} s", spent.as_secs_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_runs_while_samples_come_in_restarts_and_stops() {
        let ms = Duration::from_millis;
        let mut c = SampleClock::default();
        assert_eq!(c.tick(1, 4, ms(10)), Duration::ZERO);
        assert_eq!(c.tick(2, 4, ms(10)), ms(10));
        assert_eq!(c.tick(3, 4, ms(10)), ms(20));
        assert_eq!(c.tick(4, 4, ms(10)), ms(30));
        // All in: the clock stops.
        assert_eq!(c.tick(4, 4, ms(10)), ms(30));
        // The view moved: the pass starts again, and so does the clock.
        assert_eq!(c.tick(1, 4, ms(10)), Duration::ZERO);
        assert_eq!(c.tick(2, 4, ms(10)), ms(10));
        assert_eq!(SampleClock::line(2, 4, ms(1500)), "2 of 4 samples, 1.5 s");
    }
}
