//! One judged run for any task: the task runs in the simulator through a
//! [`SimDriver`], its judge (from `tabula_sim::judge`) looks at the settled world
//! before, watches every step and the task's moments, and gives the verdict on the
//! settled world after.

use tabula_geom::Pose;
use tabula_robot::robots::NamedRobot;
use tabula_sim::judge::{self, ClearJudge, Judge, PlacementJudge, StablePlaceJudge, TidyStart};
use tabula_sim::{SimDriver, SimError, SimWorld};
use tabula_tasks::place::{PlaceOutcome, PlaceParams};
use tabula_tasks::task::{Clear, PickPlace, Place, Task};
use tabula_tasks::tidy::Tidy;

/// A task the simulator can judge.
pub trait Judged: Task {
    type Judge: Judge;
    /// What the judge is told of the workcell besides the request (clearing: the table
    /// and the bin; tidying: the furniture to clear).
    type Ground;
    /// The judge of `robot` doing `request` in the settled `world`.
    fn judge(
        world: &SimWorld,
        robot: &str,
        request: &Self::Request,
        ground: &Self::Ground,
    ) -> Result<Self::Judge, SimError>;
    /// What the task's outcome tells its judge (placing: where it planned the object
    /// to rest).
    fn told(outcome: &Self::Outcome, params: &Self::Params) -> <Self::Judge as Judge>::Told;
}

/// The verdict a judged task's run gets.
pub type Verdict<T> = <<T as Judged>::Judge as Judge>::Verdict;

/// Runs task `T` with the robot `robot` (its name in the world, and the robot) in
/// `world`, judged: the outcome, the verdict and the world afterwards. `on_start` sees
/// the driver before the task does (a recorder starts there); camera noise from `seed`.
pub fn run_judged<T: Judged>(
    world: SimWorld,
    (name, robot): (&str, &NamedRobot),
    (request, params, ground): (&T::Request, &T::Params, &T::Ground),
    seed: u64,
    on_start: impl FnOnce(&mut SimDriver),
) -> Result<(T::Outcome, Verdict<T>, SimWorld), SimError> {
    judge::run(
        world,
        name,
        seed,
        |w| T::judge(w, name, request, ground),
        |driver, hook| {
            on_start(driver);
            let outcome = T::run(driver, robot, request, params, &mut |d, m| {
                hook(d, m.judged())
            });
            let told = T::told(&outcome, params);
            (outcome, told)
        },
    )
}

/// [`run_judged`] with the world's robot called `robot` (its first without a name).
pub fn run_in<T: Judged>(
    world: SimWorld,
    robot: Option<&str>,
    asked: (&T::Request, &T::Params, &T::Ground),
    seed: u64,
    on_start: impl FnOnce(&mut SimDriver),
) -> anyhow::Result<(T::Outcome, Verdict<T>, SimWorld)> {
    let (name, named) = crate::scene_robot_named(&world, robot)?;
    Ok(run_judged::<T>(
        world,
        (&name, &named),
        asked,
        seed,
        on_start,
    )?)
}

impl Judged for Clear {
    type Judge = ClearJudge;
    /// The table to clear and the bin to clear it into (furniture names).
    type Ground = (String, String);

    fn judge(
        world: &SimWorld,
        robot: &str,
        _: &Self::Request,
        (table, bin): &(String, String),
    ) -> Result<ClearJudge, SimError> {
        ClearJudge::new(world, robot, (table, bin))
    }

    fn told(_: &Self::Outcome, _: &Self::Params) {}
}

impl Judged for Place {
    type Judge = StablePlaceJudge;
    type Ground = ();

    fn judge(
        world: &SimWorld,
        robot: &str,
        _: &Self::Request,
        _: &(),
    ) -> Result<StablePlaceJudge, SimError> {
        StablePlaceJudge::new(world, robot)
    }

    fn told(outcome: &PlaceOutcome, params: &PlaceParams) -> Option<Pose> {
        planned_rest(outcome, params)
    }
}

/// Where placing expects the object to rest: the tool's planned pose lowered by the
/// release height (none when the task failed).
pub fn planned_rest(out: &PlaceOutcome, params: &PlaceParams) -> Option<Pose> {
    use tabula_geom::{Quat, Vec3};
    let p = out.report.planned_world_from_tool?;
    out.error.is_none().then(|| {
        Pose::from_parts(
            Vec3::new(p[0], p[1], p[2]) - Vec3::Z * params.release_height,
            Quat::from_xyzw(p[3], p[4], p[5], p[6]),
        )
    })
}

impl Judged for PickPlace {
    type Judge = PlacementJudge;
    type Ground = ();

    fn judge(
        world: &SimWorld,
        robot: &str,
        request: &Self::Request,
        _: &(),
    ) -> Result<PlacementJudge, SimError> {
        PlacementJudge::new(world, robot, request.pick, request.place.truncate())
    }

    fn told(_: &Self::Outcome, _: &Self::Params) {}
}

impl Judged for Tidy {
    type Judge = TidyStart;
    /// The furniture to clear.
    type Ground = String;

    fn judge(
        world: &SimWorld,
        _: &str,
        _: &Self::Request,
        source: &String,
    ) -> Result<TidyStart, SimError> {
        TidyStart::of(world, source)
    }

    fn told(_: &Self::Outcome, _: &Self::Params) {}
}
