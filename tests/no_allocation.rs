//! No integrator allocates during a step: every buffer is allocated when the simulation
//! is built. A counting global allocator, with a per-thread counter so that tests running
//! in parallel do not disturb one another, checks it.

use std::alloc::{GlobalAlloc, Layout, System as SystemAllocator};
use std::cell::Cell;

use glam::DVec2;
use physframes::sim::integrators::Tolerances;
use physframes::sim::{Anchor, ForceSpec, IntegratorKind, Selection, Simulation, State, System};

/// The system allocator, counting the allocations made by each thread.
struct Counting;

thread_local! {
    // A `const` thread-local without a destructor never allocates, so the allocator
    // may use it.
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { SystemAllocator.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { SystemAllocator.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { SystemAllocator.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

#[test]
fn no_integrator_allocates_while_stepping() {
    // The counter must see an allocation, or the test below would prove nothing.
    let probe = allocations();
    drop(std::hint::black_box(vec![0u8; 16]));
    assert!(
        allocations() > probe,
        "the counting allocator is not in use"
    );

    let forces = [
        ForceSpec::Gravity {
            g: DVec2::new(0.0, -9.81),
            bodies: Selection::All,
        },
        ForceSpec::Drag {
            k: 0.2,
            bodies: Selection::Bodies(vec![1]),
        },
        ForceSpec::QuadraticDrag {
            c: 0.05,
            bodies: Selection::All,
        },
        ForceSpec::TimeVarying {
            f0: DVec2::ZERO,
            f1: DVec2::new(2.0, 0.0),
            bodies: Selection::All,
            at: None,
        },
        ForceSpec::Spring {
            a: 0,
            b: Anchor::Body(1),
            stiffness: 30.0,
            rest_length: 1.0,
            damping: 0.3,
            a_at: None,
            b_at: None,
        },
        ForceSpec::Spring {
            a: 1,
            b: Anchor::Point(DVec2::new(0.0, 2.0)),
            stiffness: 10.0,
            rest_length: 0.0,
            damping: 0.0,
            a_at: None,
            b_at: None,
        },
        ForceSpec::Central {
            centre: DVec2::new(0.0, -3.0),
            strength: 20.0,
            bodies: Selection::Bodies(vec![0]),
        },
    ];
    let system = System::new(vec![1.0, 2.0], &forces);
    let initial = State::new(
        0.0,
        vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.5)],
        vec![DVec2::new(1.0, 0.0), DVec2::new(0.0, -1.0)],
    );
    for &kind in IntegratorKind::ALL {
        let mut sim = Simulation::new(system.clone(), initial.clone(), kind, 0.01)
            .with_tolerances(Tolerances::both(1e-8));
        let before = allocations();
        sim.run_steps(50).expect("finite");
        for frame in 1..=30 {
            sim.advance_to(1.0 + f64::from(frame) / 30.0)
                .expect("finite");
        }
        sim.reset(&initial);
        sim.advance_to(0.5).expect("finite");
        let during = allocations() - before;
        assert_eq!(during, 0, "{kind} allocated {during} times while stepping");
    }
}
