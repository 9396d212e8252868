//! Error budgets (`trueaxis::budget`): allocation, configurations, miniaturisation, sensitivity.

mod allocate;
mod configurations;
mod miniaturisation;
mod sensitivity;
