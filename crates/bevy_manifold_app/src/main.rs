//! The `bevy_manifold` command line: with no arguments the explorer (a
//! window into the manifold, or without a display `explorer.png`); with a
//! command, inspect, export, render and benchmark spaces.

fn main() -> std::process::ExitCode {
    private_runtime_dir();
    bevy_manifold_app::cli::run()
}

/// Gives the process a private runtime directory when the session has
/// none (no desktop login: a container, an SSH shell, CI), as a desktop
/// session would: without one the windowing and Vulkan libraries print
/// `XDG_RUNTIME_DIR is invalid or not set` several times before anything
/// useful. The directory is the user's own (mode 0700) under the
/// temporary directory, made once and reused.
fn private_runtime_dir() {
    #[cfg(unix)]
    {
        use std::os::unix::fs::{MetadataExt, PermissionsExt};
        let set = std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
        if set {
            return;
        }
        // The user's id, where /proc tells it; else this process's id.
        let who = std::fs::metadata("/proc/self")
            .map_or_else(|_| format!("p{}", std::process::id()), |m| m.uid().to_string());
        let dir = std::env::temp_dir().join(format!("bevy_manifold-runtime-{who}"));
        let private = std::fs::create_dir_all(&dir)
            .and_then(|()| std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700)))
            .and_then(|()| std::fs::metadata(&dir))
            .is_ok_and(|m| m.is_dir() && m.mode() & 0o077 == 0);
        if private {
            // SAFETY: called first thing in `main`, before any thread is
            // started, so nothing reads the environment concurrently.
            unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        }
    }
}
