//! How a coug process is asked to stop: SIGINT (Ctrl-C) or SIGTERM, the two signals
//! pAntler's teardown sends (SIGINT, then SIGTERM three seconds later). Every long-running
//! command waits on [`shutdown`], so each stops the same way.

/// Completes when the process receives SIGINT or SIGTERM (on non-Unix systems, Ctrl-C).
/// If a handler cannot be installed, that signal is simply not awaited (the other one, and
/// the default action of the OS, still stop the process).
pub async fn shutdown() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let term = async {
            match signal(SignalKind::terminate()) {
                Ok(mut s) => {
                    s.recv().await;
                }
                Err(_) => std::future::pending::<()>().await,
            }
        };
        let int = async {
            if tokio::signal::ctrl_c().await.is_err() {
                std::future::pending::<()>().await;
            }
        };
        tokio::select! {
            _ = term => {}
            _ = int => {}
        }
    }
    #[cfg(not(unix))]
    {
        if tokio::signal::ctrl_c().await.is_err() {
            std::future::pending::<()>().await;
        }
    }
}
