//! A pass's pipelines kept for each draw target they were made for (colour format,
//! samples per pixel, motion target): switching the look or the samples back and forth makes nothing
//! again. Making them again each time cost lavapipe about 25 MiB of host memory it
//! kept over a soak's first 400 frames (`grass soak`, 256 blades at 64x64), and every
//! switch in the viewer a recompile. At most 2 formats × 4 sample counts are kept.

use anyhow::Result;
use ash::vk;

/// What a pipeline draws into.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct DrawTarget {
    /// The colour's format.
    pub format: vk::Format,
    /// Samples per pixel.
    pub samples: vk::SampleCountFlags,
    /// A motion target follows the colour (temporal anti-aliasing, written by the
    /// fragment stages).
    pub motion: bool,
    /// The natural look's shaded view writes its blades' visibility into the colour,
    /// shaded after the draw (`passes::shade`; one sample per pixel).
    pub deferred: bool,
    /// The depth is reversed (1 near, 0 far: a caller's, as Bevy's): the depth
    /// test keeps the greater.
    pub reverse_z: bool,
}

impl DrawTarget {
    /// Colour of `format` at one sample, without motion.
    pub fn single(format: vk::Format) -> Self {
        Self {
            format,
            samples: vk::SampleCountFlags::TYPE_1,
            motion: false,
            deferred: false,
            reverse_z: false,
        }
    }

    /// The depth test of pipelines drawing here.
    pub fn depth_compare(&self) -> vk::CompareOp {
        if self.reverse_z {
            vk::CompareOp::GREATER_OR_EQUAL
        } else {
            vk::CompareOp::LESS_OR_EQUAL
        }
    }

    /// The second colour attachment of a pipeline drawing here: the motion target,
    /// written by the fragment stage (`written`) or kept, where there is one.
    pub fn second_color(&self, written: bool) -> Option<(vk::Format, bool)> {
        self.motion.then_some((MOTION_FORMAT, written))
    }
}

/// Format of the motion target: each pixel's own motion beyond the camera's (a
/// blade's sway; normalized device coordinates), two half floats. Four (with the
/// blade's clip w, to tell it from what was drawn over it) made the NVIDIA H100's
/// natural grass pass 1.76 ms slower than without the target at 1 M blades from the
/// edge.
pub const MOTION_FORMAT: vk::Format = vk::Format::R16G16_SFLOAT;

/// One `T` (a pass's pipelines) for each draw target it was made for, and the one in
/// use.
pub struct ByTarget<T> {
    made: Vec<(DrawTarget, T)>,
    current: usize,
}

impl<T> ByTarget<T> {
    /// `value`, made for `target`, in use.
    pub fn new(target: DrawTarget, value: T) -> Self {
        Self {
            made: vec![(target, value)],
            current: 0,
        }
    }

    /// Uses the one made for `target`, or makes it (`make`) the first time.
    pub fn select(&mut self, target: DrawTarget, make: impl FnOnce() -> Result<T>) -> Result<()> {
        self.current = match self.made.iter().position(|(t, _)| *t == target) {
            Some(i) => i,
            None => {
                self.made.push((target, make()?));
                self.made.len() - 1
            }
        };
        Ok(())
    }

    /// The one in use.
    pub fn current(&self) -> &T {
        &self.made[self.current].1
    }

    /// The one in use, to change.
    pub fn current_mut(&mut self) -> &mut T {
        &mut self.made[self.current].1
    }

    /// How many are kept.
    pub fn kept(&self) -> usize {
        self.made.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each target's value is made once, whatever the order of the switches.
    #[test]
    fn each_target_is_made_once() {
        let one = vk::SampleCountFlags::TYPE_1;
        let four = vk::SampleCountFlags::TYPE_4;
        let (srgb, hdr) = (vk::Format::B8G8R8A8_SRGB, vk::Format::R16G16B16A16_SFLOAT);
        let t = |format, samples| DrawTarget {
            format,
            samples,
            motion: false,
            deferred: false,
            reverse_z: false,
        };
        let mut made = 0;
        let mut kept = ByTarget::new(t(srgb, one), "srgb 1");
        for (target, name) in [
            (t(hdr, four), "hdr 4"),
            (t(srgb, one), "srgb 1"),
            (t(hdr, four), "hdr 4"),
            (t(srgb, four), "srgb 4"),
            (t(hdr, four), "hdr 4"),
        ] {
            kept.select(target, || {
                made += 1;
                Ok(name)
            })
            .unwrap();
            assert_eq!(*kept.current(), name);
        }
        assert_eq!((made, kept.kept()), (2, 3));
    }
}
