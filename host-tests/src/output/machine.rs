//! The machine a measurement ran on: CPU model, hardware threads,
//! compiler and date.

/// The CPU model from `/proc/cpuinfo` ("unknown CPU" where there is none).
#[must_use]
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// One line naming the machine, compiler and date of a measurement.
#[must_use]
pub fn machine_line() -> String {
    let cpu = cpu_model();
    let run = |cmd: &str, args: &[&str]| {
        std::process::Command::new(cmd)
            .args(args)
            .output()
            .ok()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| format!("{cmd}: unavailable"))
    };
    format!(
        "{cpu}, {} hardware threads (shared with other jobs), {}, {}",
        std::thread::available_parallelism().map_or(0, usize::from),
        run("rustc", &["-V"]),
        run("date", &["-u", "+%Y-%m-%d %H:%M UTC"]),
    )
}
