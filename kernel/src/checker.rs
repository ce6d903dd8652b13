//! The whole-program check ahead of the path: in the preparation thread that feeds the
//! channel, a second preparation of the same program with the check on (prep/whole.rs) runs
//! ahead of the first. No segment of a compensation run goes to the channel before the
//! checker has met the whole run; a violation — or any alarm inside the run, after which
//! the rest of the run cannot be checked — stops the path before the run it lies in.
//! The checker prepares far faster than the machine runs (docs/benchmarks.md), so the path
//! waits for it only where a long run begins.

use crate::alarm::Alarm;
use crate::handover::Job;
use crate::prep::{Preparation, Prepared, WholeMode};
use crate::segment::Role;

/// The path as the channel takes it: `first`, then every record of `prep`; with a checker,
/// no segment of a compensation run before the checker has met the whole run, and the
/// violation in its place when it lies in the run or before it.
pub struct Gated<'a> {
    prep: Preparation<'a>,
    first: std::vec::IntoIter<Prepared>,
    checker: Option<Checker<'a>>,
    runs: Runs,
    /// The load-time check refused the program: this alarm is the whole path.
    refused: Option<Alarm>,
    ended: bool,
}

impl<'a> Gated<'a> {
    pub fn new(prep: Preparation<'a>, first: Vec<Prepared>, checker: Option<Checker<'a>>) -> Self {
        Gated {
            prep,
            first: first.into_iter(),
            checker,
            runs: Runs::default(),
            refused: None,
            ended: false,
        }
    }

    /// As [`Gated::of_job`], checked at load as the kernel does (up to
    /// `trc.check_at_load_blocks`): a violation there is the path's only record, an alarm
    /// before anything moves (`softnc simulate`, tests).
    pub fn of_job_checked(job: Job<'a>) -> Self {
        let mut g = Gated::of_job(job);
        // SINUMERIK structures are read through the whole text first (cheap): one left open
        // refuses the program before anything moves, wherever it stands.
        let structure =
            crate::Interpreter::new(job.name, job.source, job.md, job.tools).structure_alarm();
        g.refused = structure.or_else(|| g.check_ahead(u64::from(job.md.trc.check_at_load_blocks)));
        g
    }

    /// The path of `job` as the kernel's channel takes it: its preparation, with the checker
    /// its machine data asks for.
    pub fn of_job(job: Job<'a>) -> Self {
        let prep = Preparation::starting_at(job.name, job.source, job.md, job.tools, job.at)
            .with_soft_limits(job.md);
        Gated::new(prep, Vec::new(), Checker::new(job))
    }

    /// Checks at most `blocks` blocks ahead of the path (less if the program ends first): the
    /// violation found there, if any (none without a checker).
    pub fn check_ahead(&mut self, blocks: u64) -> Option<Alarm> {
        self.checker.as_mut().and_then(|c| c.ahead(blocks))
    }

    /// The alarm the load-time check refused the program with ([`Gated::of_job_checked`]).
    pub fn refusal(&self) -> Option<&Alarm> {
        self.refused.as_ref()
    }

    /// The kept macro variables as the path's program (not the checker's) left them.
    pub fn kept_variables(&self) -> Option<Vec<(u32, f64)>> {
        self.prep.kept_variables()
    }

    /// Where the program starts: the position before its first motion.
    pub fn start(&self) -> crate::frontend::block::AxisPos {
        self.prep.start()
    }

    /// The next record of the path; `None` at its end.
    pub fn next_item(&mut self) -> Option<Result<Prepared, Alarm>> {
        if self.ended {
            return None;
        }
        if let Some(a) = self.refused.take() {
            self.ended = true;
            return Some(Err(a));
        }
        let item = match self.first.next() {
            Some(p) => Ok(p),
            None => self.prep.next_item().transpose()?,
        };
        if let (Ok(Prepared::Segment(s)), Some(c)) = (&item, self.checker.as_mut()) {
            if let Err(a) = c.clear(self.runs.on(s.role)) {
                return Some(Err(a));
            }
        }
        Some(item)
    }
}

/// Compensation runs as the path passes them: a run begins with an approach, or with a
/// contour piece after a stretch without compensation; the segments before the first run
/// are run 0, and what follows a run's retract counts with that run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Runs {
    run: u32,
    inside: bool,
}

impl Runs {
    /// The run a segment of role `role`, the next of the path, belongs to.
    pub fn on(&mut self, role: Role) -> u32 {
        match role {
            Role::Approach => {
                self.run += 1;
                self.inside = true;
            }
            Role::Contour | Role::Corner | Role::Intermediate if !self.inside => {
                self.run += 1;
                self.inside = true;
            }
            Role::Contour | Role::Corner | Role::Intermediate => {}
            Role::Retract | Role::Uncompensated => self.inside = false,
        }
        self.run
    }
}

pub struct Checker<'a> {
    prep: Preparation<'a>,
    runs: Runs,
    /// Runs met in full (`u32::MAX`: the whole program).
    cleared: u32,
    /// A violation, and the run it lies in.
    violation: Option<(u32, Alarm)>,
    /// The whole-program check is on (otherwise only software limits are checked ahead).
    whole: bool,
}

impl<'a> Checker<'a> {
    /// The checker for `job`, if its machine data asks for the whole-program check or has
    /// software limits (a move past one is refused before motion as well).
    fn new(job: Job<'a>) -> Option<Self> {
        let md = job.md;
        let limits = md
            .axes
            .configured()
            .any(|(_, a)| a.software_limits.is_some());
        (md.trc.whole_program_check || limits).then(|| {
            let prep = Preparation::starting_at(job.name, job.source, md, job.tools, job.at)
                .with_soft_limits(md);
            Checker {
                prep: if md.trc.whole_program_check {
                    prep.checking_whole(WholeMode::Stop)
                } else {
                    prep
                },
                runs: Runs::default(),
                cleared: 0,
                violation: None,
                whole: md.trc.whole_program_check,
            }
        })
    }

    /// Checks ahead until run `run` is met in full: the violation that stops the path
    /// before it, if one lies in it or before it.
    fn clear(&mut self, run: u32) -> Result<(), Alarm> {
        while self.cleared < run && self.violation.is_none() {
            self.step();
        }
        match &self.violation {
            Some((at, a)) if *at <= run => Err(a.clone()),
            _ => Ok(()),
        }
    }

    /// Checks at most `blocks` blocks ahead (less if the program ends first): the
    /// violation found there, if any.
    fn ahead(&mut self, blocks: u64) -> Option<Alarm> {
        while self.cleared < u32::MAX && self.violation.is_none() && self.prep.blocks() < blocks {
            self.step();
        }
        self.violation.as_ref().map(|(_, a)| a.clone())
    }

    /// One record of the checker's preparation.
    fn step(&mut self) {
        match self.prep.next_item() {
            Ok(Some(Prepared::Segment(s))) => {
                let run = self.runs.on(s.role);
                self.cleared = self.cleared.max(run.saturating_sub(1));
            }
            Ok(Some(_)) => {}
            Ok(None) => self.cleared = u32::MAX,
            // An alarm inside a compensation run ends the checker's preparation before the
            // whole check has met the rest of the run, where an element may lie that a
            // segment already out reaches: the run is not cleared. (The window's own 3021
            // comes only after the segments it let go.)
            // A software limit is a violation wherever it lies: the path must not start a
            // move it cannot finish.
            Err(a)
                if a.code == crate::AlarmCode::SoftwareLimit
                    || (self.whole && (self.prep.stopped_by_whole_check() || self.runs.inside)) =>
            {
                self.violation = Some((self.runs.run, a));
            }
            // Outside a run an alarm ends preparation at the same place in the path that
            // feeds the channel: everything before it is checked.
            Err(_) => self.cleared = u32::MAX,
        }
    }
}
