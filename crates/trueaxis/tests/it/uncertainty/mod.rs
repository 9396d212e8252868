//! Uncertainty (`trueaxis::uncertainty`): Monte Carlo against known outputs, the linear map, the KX8-Five campaign.

mod known_outputs;
mod kx8five;
mod kx8five_table5;
mod linear_map;
