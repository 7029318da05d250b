//! grains across processes. Every build carries [`launch`], which tells whether the
//! program was started by `mpirun` on several ranks; with the `mpi` feature,
//! [`World`] implements the DEM engine's seams ([`grains_dem::Reduce`],
//! [`grains_dem::Exchange`]) over MPI (rsmpi on the system's MPI), so the engines never
//! see MPI themselves.
//!
//! What is here: the reductions, in rank order, the point-to-point messages the
//! engine's domain decomposition ([`grains_dem::decomp`]) sends, and the launch checks.
//! `grains run` and `grains resume` (DEM, 2D and 3D) and `grains bench dem` run over it
//! on several ranks; which commands and scenarios do not yet is in docs/parallel.md.

#[cfg(feature = "mpi")]
mod world;

#[cfg(feature = "mpi")]
pub use world::World;

/// The variables the MPI launchers set in every process they start, with the number
/// of ranks: OpenMPI, then MPICH and Intel MPI (PMI), then Slurm's `srun`.
const SIZE_VARS: [&str; 4] = [
    "OMPI_COMM_WORLD_SIZE",
    "PMI_SIZE",
    "PMIX_SIZE",
    "SLURM_NTASKS",
];

/// How this process was started.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Launch {
    /// Number of ranks the launcher started (1 without a launcher).
    pub ranks: usize,
    /// This process's rank (0 without a launcher).
    pub rank: usize,
}

/// How the launcher (if any) started this process, read from its environment: a binary
/// built without MPI can still see that it is one of several.
pub fn launch() -> Launch {
    launch_from(|k| std::env::var(k).ok())
}

fn launch_from(var: impl Fn(&str) -> Option<String>) -> Launch {
    let num = |k: &str| var(k).and_then(|v| v.trim().parse::<usize>().ok());
    let ranks = SIZE_VARS.iter().find_map(|k| num(k)).unwrap_or(1).max(1);
    let rank = [
        "OMPI_COMM_WORLD_RANK",
        "PMI_RANK",
        "PMIX_RANK",
        "SLURM_PROCID",
    ]
    .iter()
    .find_map(|k| num(k))
    .unwrap_or(0);
    Launch { ranks, rank }
}

/// Whether this build can run on several ranks.
pub const ENABLED: bool = cfg!(feature = "mpi");

/// Why this build cannot run as launched, as one line naming the value, or `None` when
/// it can: a binary built without the `mpi` feature started on several ranks would run
/// the whole problem once per rank, all writing into one directory. (A build with the
/// feature goes on; which commands run on several ranks is the command line's to say.)
pub fn refuse(launch: Launch) -> Option<String> {
    if launch.ranks <= 1 || ENABLED {
        return None;
    }
    Some(format!(
        "rank {} of {}: this grains was built without MPI (ranks = {}); allowed: 1 rank, \
         or a build with `--features mpi` (README, \"MPI\")",
        launch.rank, launch.ranks, launch.ranks
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_launcher_is_read_from_its_variables() {
        let env = |pairs: &'static [(&'static str, &'static str)]| {
            move |k: &str| {
                pairs
                    .iter()
                    .find(|(n, _)| *n == k)
                    .map(|(_, v)| v.to_string())
            }
        };
        assert_eq!(launch_from(env(&[])), Launch { ranks: 1, rank: 0 });
        let ompi = launch_from(env(&[
            ("OMPI_COMM_WORLD_SIZE", "4"),
            ("OMPI_COMM_WORLD_RANK", "3"),
        ]));
        assert_eq!(ompi, Launch { ranks: 4, rank: 3 });
        let mpich = launch_from(env(&[("PMI_SIZE", "2"), ("PMI_RANK", "1")]));
        assert_eq!(mpich, Launch { ranks: 2, rank: 1 });
        assert!(refuse(Launch { ranks: 1, rank: 0 }).is_none());
        // A build with MPI goes on; one without says so on each rank.
        let line = refuse(ompi);
        assert_eq!(line.is_some(), !ENABLED);
        if let Some(line) = line {
            assert!(
                line.contains("rank 3 of 4") && line.contains("ranks = 4"),
                "{line}"
            );
        }
    }
}
