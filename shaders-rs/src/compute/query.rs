//! The questions a game asks of the grass (`shared::query`), answered over every
//! simulated blade: each blade's part added to each answer by device atomics; and
//! the colliders touching the blades of the collision pass, marked after it.

use super::cut::cut_now;
use shared::Blade;
use shared::gpu::counters::COUNTER_NEAR;
use shared::gpu::layout::{
    CULL_WORKGROUP, FrameUniforms, NEAR_LIST, SIMULATE_WORKGROUP, flat_index,
};
use shared::query::{ASKED, MAX_QUESTIONS, Question, contact_bit};
use shared::sim::collide::Collider;
use shared::sim::grid::{NONE_TOUCHING, Nearby};
use spirv_std::arch::{atomic_i_add, atomic_or, workgroup_memory_barrier_with_group_sync};
use spirv_std::glam::{UVec3, UVec4};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// One thread per simulated blade, as the cut table leaves it (`cut_now`): its part
/// in each question the frame asks (`Question::part`, whole fixed-point units), added
/// to that question's answer where it has one; a blade of no part adds nothing. The
/// workgroup reads the questions once into workgroup memory: each thread reading
/// them from the query buffer took 16 questions over 4 M blades 1.9 ms on the NVIDIA
/// H200.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn answer_questions(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 28)] cuts: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 29)] queries: &mut [u32],
    #[spirv(workgroup)] asked_here: &mut [Question; MAX_QUESTIONS],
) {
    let asked = (queries[ASKED] as usize).min(MAX_QUESTIONS);
    if (local as usize) < asked {
        asked_here[local as usize] = Question::read(queries, local as usize);
    }
    workgroup_memory_barrier_with_group_sync();
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    if index >= frame.grass.simulated {
        return;
    }
    let blade = cut_now(&blades[index as usize], frame, cuts);
    let mut q = 0;
    while q < asked {
        let part = asked_here[q].part(&blade);
        if part.blades > 0 {
            part.add_to(q, |at, value| add(&mut queries[at], value));
        }
        q += 1;
    }
}

/// One thread per blade of the collision pass (its indirect dispatch, after it): marks
/// the first collider the blade, as the pass left it, touches
/// (`Nearby::first_touching`). A blade the pass over every blade kept had no
/// collider's bounding sphere about its tip or midpoint: it touches none.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(128)))]
pub fn mark_contacts(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 25)] colliders: &[Collider],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] grid: &[u32],
    // The same buffer four words at a time (`Nearby::shapes`).
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] shapes: &[UVec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 27)] near: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 29)] queries: &mut [u32],
) {
    let i = flat_index(id, workgroups, CULL_WORKGROUP);
    if i >= counters[COUNTER_NEAR] {
        return;
    }
    let blade = blades[near[NEAR_LIST + i as usize] as usize];
    let nearby = Nearby {
        colliders,
        words: grid,
        shapes,
        grid: frame.collider_grid,
    };
    let count = frame.forces.colliders;
    let slot = nearby.around(blade.root(), blade.height(), count);
    let touched = nearby.first_touching((blade.tip(), blade.midpoint()), &slot, count);
    if touched != NONE_TOUCHING {
        mark_contact(queries, touched);
    }
}

/// Marks `collider` as touching a blade this frame (`query::CONTACTS`), with a
/// device atomic.
fn mark_contact(queries: &mut [u32], collider: u32) {
    let (at, bit) = contact_bit(collider);
    unsafe {
        atomic_or::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
            &mut queries[at],
            bit,
        );
    }
}

/// Adds `value` to `word` with a device atomic, where it is not 0.
fn add(word: &mut u32, value: u32) {
    if value > 0 {
        unsafe {
            atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(word, value);
        }
    }
}
