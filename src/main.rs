//! `hysteron`: the command-line program (see `hysteron --help`).
//!
//! * `hysteron paper [--out DIR]`: runs the paper's experiments, writes a
//!   CSV per experiment and the figures (see [`hysteron::paper`]);
//! * `hysteron simulate --model SPEC.json --input IN.csv [--column x]
//!   --output OUT.csv [--plot LOOP.svg]`: runs a model spec over one column
//!   of a CSV file (see [`hysteron::simulate`]).
//!
//! Errors are one line on stderr (`error: ...`) and exit code 1; usage
//! errors are clap's, exit code 2.

use clap::{Parser, Subcommand};
use hysteron::{csvio, paper, simulate};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "hysteron",
    version,
    about = "Hysteresis operators: the paper's experiments, and model specs run over CSV data"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the experiments of Ruderman & Bertram (2015): one CSV per
    /// experiment (t,x,F,z,slider,friction,h) and the figures loops.svg,
    /// chirp.svg and stiffness.svg; prints a summary.
    Paper {
        /// Output directory (created if missing).
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
    },
    /// Run a model spec (JSON) over one column of a CSV file (with a
    /// header); the output holds all input columns plus `y`.
    Simulate {
        /// The model spec (JSON, see hysteron::models::Spec).
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// The input CSV file, with a header row.
        #[arg(long, value_name = "IN.csv")]
        input: PathBuf,
        /// The input column.
        #[arg(long, value_name = "NAME", default_value = "x")]
        column: String,
        /// The output CSV file (written atomically; may not be the input).
        #[arg(long, value_name = "OUT.csv")]
        output: PathBuf,
        /// Also draw y over the input column as an SVG figure.
        #[arg(long, value_name = "LOOP.svg")]
        plot: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Paper { out } => paper::run(&paper::PaperOptions { out })
            .map(|report| println!("{report}"))
            .map_err(|e| e.to_string()),
        Command::Simulate {
            model,
            input,
            column,
            output,
            plot,
        } => simulate::run(&simulate::SimulateOptions {
            model,
            input,
            column,
            output,
            plot,
        })
        .map(|report| println!("{report}"))
        .map_err(|e| e.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", csvio::one_line(&e));
            ExitCode::FAILURE
        }
    }
}
