//! Running a render: the driver loop (budgets, shards, interruption, progress, checkpoints), the
//! checkpoint format, and the job that takes a scene file to an image.

pub mod aovs;
pub mod assemble;
pub mod checkpoint;
pub mod default_light;
pub mod driver;
pub mod header;
pub mod interrupt;
pub mod job;
pub mod memory;
pub mod overrides;
pub mod pilot;
pub mod prepare;
pub mod run;
pub mod sensors;
