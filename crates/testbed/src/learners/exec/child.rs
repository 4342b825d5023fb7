//! A child process that speaks in lines: lines written to its stdin, lines
//! read from its stdout within a time limit, the last lines of its stderr
//! kept for error messages. Dropping it ends the process.

use std::collections::VecDeque;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::process::{ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How many of the child's last stderr lines an error quotes.
const STDERR_LINES: usize = 12;

/// How long a child has to exit once told the trial is over, before it is
/// killed.
const EXIT_GRACE: Duration = Duration::from_secs(2);

/// Why a line could not be exchanged.
#[derive(Debug, Clone, PartialEq)]
pub enum Fault {
    /// The child has gone: how it ended, if known.
    Gone(Option<String>),
    /// No line within the time limit, s.
    Silent(f64),
}

/// A running child process and its lines.
#[derive(Debug)]
pub struct Child {
    process: std::process::Child,
    stdin: Option<BufWriter<ChildStdin>>,
    lines: Receiver<String>,
    stderr: Arc<Mutex<VecDeque<String>>>,
}

impl Child {
    /// Starts `words[0]` with the rest as its arguments, in the current
    /// directory.
    pub fn spawn(words: &[String]) -> Result<Self, String> {
        let (program, args) = words
            .split_first()
            .ok_or("an empty command: write exec:PROGRAM ARGS...")?;
        let mut process = Command::new(program)
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start `{program}`: {e}"))?;
        let stdin = process.stdin.take().map(BufWriter::new);
        let (send, lines) = mpsc::channel();
        if let Some(out) = process.stdout.take() {
            std::thread::spawn(move || {
                for line in BufReader::new(out).lines() {
                    let Ok(line) = line else { break };
                    if send.send(line).is_err() {
                        break;
                    }
                }
            });
        }
        let stderr = Arc::new(Mutex::new(VecDeque::new()));
        if let Some(err) = process.stderr.take() {
            let tail = Arc::clone(&stderr);
            std::thread::spawn(move || {
                for line in BufReader::new(err).lines() {
                    let Ok(line) = line else { break };
                    if let Ok(mut t) = tail.lock() {
                        if t.len() == STDERR_LINES {
                            t.pop_front();
                        }
                        t.push_back(line);
                    }
                }
            });
        }
        Ok(Self {
            process,
            stdin,
            lines,
            stderr,
        })
    }

    /// Queues one line for the child (sent at the next [`Child::receive`]
    /// or when the buffer fills).
    pub fn send(&mut self, line: &str) -> Result<(), Fault> {
        let stdin = self.stdin.as_mut().ok_or(Fault::Gone(None))?;
        if stdin
            .write_all(line.as_bytes())
            .and_then(|()| stdin.write_all(b"\n"))
            .is_err()
        {
            return Err(Fault::Gone(self.ended()));
        }
        Ok(())
    }

    /// Sends what is queued and waits up to `limit` for the child's next line.
    pub fn receive(&mut self, limit: Duration) -> Result<String, Fault> {
        if let Some(stdin) = self.stdin.as_mut() {
            if stdin.flush().is_err() {
                return Err(Fault::Gone(self.ended()));
            }
        }
        match self.lines.recv_timeout(limit) {
            Ok(line) => Ok(line),
            Err(RecvTimeoutError::Timeout) => Err(Fault::Silent(limit.as_secs_f64())),
            Err(RecvTimeoutError::Disconnected) => Err(Fault::Gone(self.ended())),
        }
    }

    /// A line the child wrote that nobody has asked for yet, if any.
    pub fn unasked(&self) -> Option<String> {
        self.lines.try_recv().ok()
    }

    /// How the child ended, waiting a moment for it (its stdout closed or
    /// its stdin broke, so it is ending or has ended).
    fn ended(&mut self) -> Option<String> {
        let until = Instant::now() + EXIT_GRACE;
        loop {
            match self.process.try_wait() {
                Ok(Some(status)) => return Some(describe(status)),
                Ok(None) if Instant::now() < until => {
                    std::thread::sleep(Duration::from_millis(5));
                }
                _ => return None,
            }
        }
    }

    /// The last lines the child wrote to stderr, indented, or a note that
    /// there were none.
    pub fn stderr_tail(&self) -> String {
        // The stderr thread may still be reading the child's last words.
        std::thread::sleep(Duration::from_millis(20));
        let lines: Vec<String> = self
            .stderr
            .lock()
            .map(|t| t.iter().cloned().collect())
            .unwrap_or_default();
        if lines.is_empty() {
            "it wrote nothing to stderr".into()
        } else {
            format!(
                "the last lines of its stderr:\n    {}",
                lines.join("\n    ")
            )
        }
    }

    /// Sends `last`, closes the child's stdin and waits a moment for it to
    /// exit, then kills it.
    pub fn finish(&mut self, last: &str) {
        let _ = self.send(last);
        if let Some(mut stdin) = self.stdin.take() {
            let _ = stdin.flush();
        }
        let until = Instant::now() + EXIT_GRACE;
        while matches!(self.process.try_wait(), Ok(None)) && Instant::now() < until {
            std::thread::sleep(Duration::from_millis(2));
        }
        let _ = self.process.kill();
        let _ = self.process.wait();
    }
}

impl Drop for Child {
    fn drop(&mut self) {
        self.stdin.take();
        let _ = self.process.kill();
        let _ = self.process.wait();
    }
}

/// An exit status in words.
fn describe(status: ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return format!("killed by signal {signal}");
        }
    }
    match status.code() {
        Some(0) => "exited (status 0) before the trial's end".into(),
        Some(code) => format!("exited with status {code}"),
        None => status.to_string(),
    }
}
