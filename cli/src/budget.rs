//! `satflock budget`: the perturbation budget of a satellite pair ([`satflock::budget`]), printed as a
//! Markdown table (or, with `--json`, as the library's [`satflock::budget::Budget`] in JSON). Every
//! value out of range is a usage error (exit 2) naming the flag and the allowed range.

use anyhow::Result;
use clap::ValueEnum;

use satflock::budget::{
    budget, BudgetError, BudgetInput, SeparationDirection, MAX_ALTITUDE_M, MAX_SEPARATION_M,
    MIN_ALTITUDE_M,
};
use satflock::dynamics::PhysicalProperties;

use crate::{print_out, usage};

/// The flags of `satflock budget`.
#[derive(clap::Args)]
pub struct BudgetArgs {
    /// Altitude of satellite 1's circular orbit above the equatorial radius [km], 100 to 2000.
    #[arg(long)]
    altitude_km: f64,
    /// Inclination of the orbit [deg], 0 to 180.
    #[arg(long)]
    inclination_deg: f64,
    /// Distance between the two satellites along the arc [m], > 0 and at most 100 000.
    #[arg(long, default_value_t = 1000.0)]
    separation_m: f64,
    /// Axis of satellite 1's Hill frame the separation is along.
    #[arg(long, value_enum, default_value = "along-track")]
    direction: DirectionArg,
    /// Mass of each satellite [kg], > 0.
    #[arg(long)]
    mass_kg: f64,
    /// Satellite 1's drag area [m^2], >= 0.
    #[arg(long)]
    drag_area_m2: f64,
    /// Satellite 2's drag area [m^2], >= 0 (default: twice --drag-area-m2, so that the differential
    /// drag, which comes from different ballistic coefficients, shows).
    #[arg(long)]
    drag_area_2_m2: Option<f64>,
    /// Drag coefficient C_d of both satellites, 0 to 10.
    #[arg(long, default_value_t = 2.2)]
    drag_coefficient: f64,
    /// Satellite 1's area facing the Sun [m^2], >= 0 (default: its drag area).
    #[arg(long)]
    srp_area_m2: Option<f64>,
    /// Satellite 2's area facing the Sun [m^2], >= 0 (default: its drag area).
    #[arg(long)]
    srp_area_2_m2: Option<f64>,
    /// Reflectivity coefficient C_r of both satellites, 0 to 2 (1 absorbs, 2 mirrors).
    #[arg(long, default_value_t = 1.5)]
    reflectivity_coefficient: f64,
    /// Atmosphere of the drag row (harris-priester: no drag above 1000 km).
    #[arg(long, value_enum, default_value = "harris-priester")]
    atmosphere: AtmosphereArg,
    /// The instant of the budget (ISO 8601 UTC): the Sun's and the Moon's positions and the
    /// atmosphere's diurnal bulge.
    #[arg(long, default_value = satflock::time::DEFAULT_EPOCH_UTC)]
    epoch_utc: String,
    /// Print the budget as JSON instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum DirectionArg {
    /// The same orbit, ahead.
    AlongTrack,
    /// A coplanar orbit, higher.
    Radial,
    /// An orbit inclined more, about the same nodes.
    CrossTrack,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum AtmosphereArg {
    /// Harris–Priester (Montenbruck & Gill), with the diurnal bulge.
    HarrisPriester,
    /// Vallado's piecewise exponential table (static).
    ExponentialTable,
}

/// Runs `satflock budget`.
pub fn budget_command(args: &BudgetArgs) -> Result<()> {
    let range = |flag: &str, value: f64, ok: bool, allowed: &str| {
        if value.is_finite() && ok {
            Ok(())
        } else {
            Err(usage(format!(
                "{flag} {value} is out of range (allowed: {allowed})"
            )))
        }
    };
    let altitude_m = args.altitude_km * 1e3;
    range(
        "--altitude-km",
        args.altitude_km,
        (MIN_ALTITUDE_M..=MAX_ALTITUDE_M).contains(&altitude_m),
        "100 to 2000 km",
    )?;
    range(
        "--inclination-deg",
        args.inclination_deg,
        (0.0..=180.0).contains(&args.inclination_deg),
        "0 to 180 deg",
    )?;
    range(
        "--separation-m",
        args.separation_m,
        args.separation_m > 0.0 && args.separation_m <= MAX_SEPARATION_M,
        "> 0 and at most 100000 m",
    )?;
    let epoch = satflock::time::parse_epoch_utc(&args.epoch_utc)
        .map_err(|m| usage(format!("--epoch-utc: {m}")))?;
    let drag_area_2_m2 = args.drag_area_2_m2.unwrap_or(2.0 * args.drag_area_m2);
    let properties = |drag_area_m2: f64, srp_area_m2: Option<f64>| PhysicalProperties {
        mass_kg: args.mass_kg,
        drag_area_m2,
        drag_coefficient: args.drag_coefficient,
        srp_area_m2: srp_area_m2.unwrap_or(drag_area_m2),
        reflectivity_coefficient: args.reflectivity_coefficient,
    };
    let input = BudgetInput {
        altitude_m,
        inclination_rad: args.inclination_deg.to_radians(),
        epoch,
        separation_m: args.separation_m,
        direction: match args.direction {
            DirectionArg::AlongTrack => SeparationDirection::AlongTrack,
            DirectionArg::Radial => SeparationDirection::Radial,
            DirectionArg::CrossTrack => SeparationDirection::CrossTrack,
        },
        satellite_1: properties(args.drag_area_m2, args.srp_area_m2),
        satellite_2: properties(drag_area_2_m2, args.srp_area_2_m2),
        drag: match args.atmosphere {
            AtmosphereArg::HarrisPriester => BudgetInput::harris_priester(),
            AtmosphereArg::ExponentialTable => BudgetInput::exponential_table(),
        },
    };
    let b = budget(&input).map_err(|e| flag_error(&e))?;
    if args.json {
        return print_out(&(serde_json::to_string_pretty(&b)? + "\n"));
    }
    let mut text = format!(
        "Perturbation budget: circular orbit at {} km, inclination {}°, epoch {} UTC; satellites {} m \
         apart, {}; drag in {}; SRP without shadow; orbit means over {} points (T = {:.1} s).\n\n\
         | term | ‖a‖ [m/s²] | ‖Δa‖ [m/s²] | drift per orbit [m] | drift per day [m] |\n\
         | --- | ---: | ---: | ---: | ---: |\n",
        args.altitude_km,
        args.inclination_deg,
        b.epoch_utc,
        args.separation_m,
        b.direction,
        match args.atmosphere {
            AtmosphereArg::HarrisPriester => "harris-priester",
            AtmosphereArg::ExponentialTable => "exponential-table",
        },
        b.samples_per_orbit,
        b.period_s,
    );
    for row in &b.terms {
        text.push_str(&format!(
            "| {} | {} | {:.3e} | {:.3e} | {:.3e} |\n",
            row.term,
            row.acceleration_mps2
                .map_or_else(|| "—".to_owned(), |a| format!("{a:.3e}")),
            row.differential_acceleration_mps2,
            row.drift_per_orbit_m,
            row.drift_per_day_m,
        ));
    }
    text.push_str(
        "\nDrift: the secular along-track drift of the HCW equations forced by the orbit mean of the \
         differential acceleration (each satellite's own RSW frame), |(3/2) a_y t² + 2 a_x t / n|; \
         periodic and once-per-orbit responses left out (docs/dynamics.md).\n",
    );
    print_out(&text)
}

/// A library error as a usage error naming the flag that set the value.
fn flag_error(e: &BudgetError) -> anyhow::Error {
    let field = e.key.rsplit('.').next().unwrap_or(&e.key);
    let second = e.key.starts_with("satellite_2.");
    let flag = match field {
        "mass_kg" => "--mass-kg",
        "drag_area_m2" if second => "--drag-area-2-m2",
        "drag_area_m2" => "--drag-area-m2",
        "drag_coefficient" => "--drag-coefficient",
        "srp_area_m2" if second => "--srp-area-2-m2",
        "srp_area_m2" => "--srp-area-m2",
        "reflectivity_coefficient" => "--reflectivity-coefficient",
        _ => return usage(e.to_string()),
    };
    usage(format!(
        "{flag} {} is out of range (allowed: {})",
        e.value, e.allowed
    ))
}
