//! What a frame answered of the questions asked of the grass (`shared::query`): each
//! question with its tally, and the colliders touching blades, from which the host
//! makes the events of a collider entering or leaving the grass (a game's footsteps).

use shared::query::{ASKED, CONTACT_WORDS, CONTACTS, MAX_QUESTIONS, Question, Tally, contact_bit};

/// The questions one frame asked, each with its answer, and the colliders it found
/// touching blades.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Answers {
    /// Each question asked, in order, with its tally over the blades.
    pub answers: Vec<(Question, Tally)>,
    /// The colliders touching blades.
    pub contacts: Contacts,
}

impl Answers {
    /// From the query buffer's words as a frame left them.
    pub fn from_words(words: &[u32]) -> Self {
        let asked = (words[ASKED] as usize).min(MAX_QUESTIONS);
        Self {
            answers: (0..asked)
                .map(|q| (Question::read(words, q), Tally::read(words, q)))
                .collect(),
            contacts: Contacts {
                words: words[CONTACTS..CONTACTS + CONTACT_WORDS]
                    .try_into()
                    .expect("contact words"),
            },
        }
    }
}

/// The colliders of a frame touching blades (a blade's tip or midpoint within
/// `shared::sim::grid::TOUCH_MARGIN` of a pushing collider's surface), one bit each.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Contacts {
    words: [u32; CONTACT_WORDS],
}

impl Default for Contacts {
    fn default() -> Self {
        Self {
            words: [0; CONTACT_WORDS],
        }
    }
}

/// A collider entering or leaving the grass between two frames.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct GrassEvent {
    /// The collider's index in its frame's colliders.
    pub collider: u32,
    /// It entered the grass (else it left it).
    pub entered: bool,
}

impl Contacts {
    /// Whether collider `i` touches blades.
    pub fn touching(&self, i: u32) -> bool {
        let (at, bit) = contact_bit(i);
        self.words.get(at - CONTACTS).is_some_and(|w| w & bit != 0)
    }

    /// The colliders touching blades, in ascending order.
    pub fn iter(&self) -> impl Iterator<Item = u32> + '_ {
        (0..(CONTACT_WORDS * 32) as u32).filter(|&i| self.touching(i))
    }

    /// The colliders that entered or left the grass since `before`, in ascending
    /// order.
    pub fn events_since(&self, before: &Contacts) -> Vec<GrassEvent> {
        (0..(CONTACT_WORDS * 32) as u32)
            .filter(|&i| self.touching(i) != before.touching(i))
            .map(|collider| GrassEvent {
                collider,
                entered: self.touching(collider),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shared::query::{Around, query_words};

    #[test]
    fn events_are_the_contacts_that_changed() {
        let mut words = query_words(&[Question::around(Around {
            centre: glam::Vec3::ZERO,
            radius: 1.0,
        })]);
        words[CONTACTS] = 0b101;
        words[CONTACTS + 1] = 1;
        let before = Answers::from_words(&words).contacts;
        assert_eq!(before.iter().collect::<Vec<_>>(), vec![0, 2, 32]);
        words[CONTACTS] = 0b110;
        words[CONTACTS + 1] = 0;
        let after = Answers::from_words(&words);
        assert_eq!(after.answers.len(), 1);
        let entered = |collider| GrassEvent {
            collider,
            entered: true,
        };
        let left = |collider| GrassEvent {
            collider,
            entered: false,
        };
        assert_eq!(
            after.contacts.events_since(&before),
            vec![left(0), entered(1), left(32)]
        );
        assert!(after.contacts.events_since(&after.contacts).is_empty());
        assert!(!after.contacts.touching(5000));
    }
}
