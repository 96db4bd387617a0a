//! The `railfem` binary: see [`railfem::cli`].

fn main() {
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_default();
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        if msg.starts_with("failed printing to std") {
            // The reader of a pipe went away (`railfem elements | head`): stop quietly with
            // the shell's code for a closed pipe (128 + SIGPIPE), as a C tool would.
            std::process::exit(141);
        }
        eprintln!("railfem: internal error{at}: {msg} — please report this with the model file");
    }));
    // A file size limit (`ulimit -f`, `prlimit --fsize`) kills a process that writes past
    // it with SIGXFSZ unless the signal is ignored; ignored, the write returns EFBIG and
    // the run stops as on a full disk: exit code 2, one line naming the file, whole lines.
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN before any thread is started.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let argv: Vec<std::ffi::OsString> = std::env::args_os().skip(1).collect();
    let code = match std::panic::catch_unwind(|| {
        railfem::cli::parse(&argv).and_then(|a| railfem::cli::run(&a))
    }) {
        Ok(Ok(code)) => code,
        Ok(Err(
            e @ (railfem::framework::FemError::Interrupted { .. }
            | railfem::framework::FemError::InterruptedAfter { .. }),
        )) => {
            // SIGINT/SIGTERM: the outputs are whole up to that step; the shell's code for
            // a run stopped by Ctrl-C (128 + SIGINT).
            eprintln!("railfem: {e}; the outputs are whole up to there (run.json says so)");
            130
        }
        Ok(Err(e)) => {
            eprintln!("error: {}", e.to_string().replace('\n', " "));
            2
        }
        Err(_) => 101,
    };
    std::process::exit(code);
}
