//! The command line's integration tests, in one binary (one link of the crate instead of one per
//! file): each module runs `trueaxis` as a user does, the modules mirror the commands of
//! crates/cli/src, and `support` holds the one runner and the helpers they share.

mod ballbar;
mod budget;
mod compensate;
mod convert;
mod demo;
mod design;
mod docs;
mod fit;
mod help;
mod identify;
mod iso230_2;
mod live;
mod nc;
mod predict;
mod reliability;
mod report;
mod reversal;
mod support;
mod thermal;
mod uncertainty;
mod verify;
