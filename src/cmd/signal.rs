//! How a coug process is asked to stop: SIGINT (Ctrl-C) or SIGTERM, the two signals
//! pAntler's teardown sends (SIGINT, then SIGTERM three seconds later). Every long-running
//! command waits on [`shutdown`], so each stops the same way.

use std::future::Future;

/// A future that completes when the process receives SIGINT or SIGTERM (on non-Unix systems,
/// Ctrl-C). The handlers are installed when this is called, not when the future is first
/// polled: a command calls it before it announces itself (an endpoint, a port), so a signal
/// sent by whoever read the announcement is never lost to the default action. Call it inside
/// a tokio runtime. If a handler cannot be installed, that signal is simply not awaited (the
/// other one, and the default action of the OS, still stop the process).
pub fn shutdown() -> impl Future<Output = ()> {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let term = signal(SignalKind::terminate()).ok();
        let int = signal(SignalKind::interrupt()).ok();
        async move {
            let wait = |s: Option<tokio::signal::unix::Signal>| async move {
                match s {
                    Some(mut s) => {
                        s.recv().await;
                    }
                    None => std::future::pending::<()>().await,
                }
            };
            tokio::select! {
                _ = wait(term) => {}
                _ = wait(int) => {}
            }
        }
    }
    #[cfg(not(unix))]
    {
        async {
            if tokio::signal::ctrl_c().await.is_err() {
                std::future::pending::<()>().await;
            }
        }
    }
}
