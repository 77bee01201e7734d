//! Shading on the AO's machinery: many point lights over N×N pixel classes ([`lights`]),
//! screen-space directional occlusion with one bounce ([`ssdo`]), the environment it
//! lights with ([`environment`]), and the prepared buffer they read ([`prepared`]).

pub mod environment;
pub mod lights;
pub mod prepared;
pub mod ssdo;
