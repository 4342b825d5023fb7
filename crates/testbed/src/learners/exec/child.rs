//! A child process that speaks in lines: lines written to its stdin, lines
//! read from its stdout within a time limit, the last lines of its stderr
//! kept for error messages. On unix it runs in a process group of its own,
//! and every way out (the end of a trial, a fault, dropping it, the host's
//! Ctrl-C) kills the whole group, so that nothing it started outlives it.

use std::collections::VecDeque;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::process::{ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

/// The longest line a child may write to stdout, bytes: past it the line is
/// a fault, and no more is read (memory stays bounded whatever it writes).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// How many of the child's last stderr lines an error quotes.
const STDERR_LINES: usize = 12;

/// How much of the child's stderr is kept whole for the trial's folder
/// (`learner_stderr.txt`), bytes; past it, only the count of what was left
/// out is kept.
pub const STDERR_KEPT_BYTES: usize = 4 << 20;

/// Everything a child wrote to its stderr, up to [`STDERR_KEPT_BYTES`].
#[derive(Debug, Default)]
pub struct StderrLog {
    text: String,
    left_out: usize,
}

impl StderrLog {
    fn push(&mut self, line: &str) {
        if self.text.len() + line.len() < STDERR_KEPT_BYTES {
            self.text.push_str(line);
            self.text.push('\n');
        } else {
            self.left_out += line.len() + 1;
        }
    }

    /// What it wrote, with a last line saying how much was left out, if any.
    pub fn text(&self) -> String {
        if self.left_out == 0 {
            self.text.clone()
        } else {
            format!(
                "{}[{} more bytes of stderr were left out: {STDERR_KEPT_BYTES} are kept]\n",
                self.text, self.left_out
            )
        }
    }
}

/// A child's stderr as it is written, shared with whoever keeps it.
pub type SharedStderr = Arc<Mutex<StderrLog>>;

/// How long a child has to exit once told the trial is over, before it is
/// killed.
const EXIT_GRACE: Duration = Duration::from_secs(2);

/// The process groups of the children running now, killed on the host's
/// Ctrl-C (a group of its own does not get the terminal's interrupt).
static LIVE_GROUPS: Mutex<Vec<u32>> = Mutex::new(Vec::new());

/// Kills every process of the group `id` (the group's leader's pid).
fn kill_group(id: u32) {
    #[cfg(unix)]
    if let Ok(pid) = i32::try_from(id) {
        use nix::sys::signal::{Signal, killpg};
        // The group may be gone already: nothing to do then.
        let _ = killpg(nix::unistd::Pid::from_raw(pid), Signal::SIGKILL);
    }
    #[cfg(not(unix))]
    let _ = id;
}

/// On the first child: a Ctrl-C handler that kills the live children's
/// groups and exits as an interrupted program does (130). A handler the
/// program set itself is left in place.
fn kill_groups_on_interrupt() {
    static SET: Once = Once::new();
    SET.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if let Ok(groups) = LIVE_GROUPS.lock() {
                groups.iter().copied().for_each(kill_group);
            }
            std::process::exit(130);
        });
    });
}

/// Why a line could not be exchanged.
#[derive(Debug, Clone, PartialEq)]
pub enum Fault {
    /// The child has gone: how it ended, if known.
    Gone(Option<String>),
    /// No line within the time limit, s.
    Silent(f64),
    /// It wrote something that is not a line of text: why.
    NotALine(String),
}

/// The lines of `from` sent to `to` as they come: each a line of UTF-8 text
/// (its end of line removed), or, once, why what came was not one (too long,
/// not UTF-8), after which nothing more is read. Reads at most
/// [`MAX_LINE_BYTES`] + 1 bytes a line.
fn send_lines(from: impl std::io::Read, to: &mpsc::Sender<Result<String, String>>) {
    use std::io::Read;
    let mut reader = BufReader::new(from);
    loop {
        let mut line = Vec::new();
        let limit = u64::try_from(MAX_LINE_BYTES + 1).unwrap_or(u64::MAX);
        match (&mut reader).take(limit).read_until(b'\n', &mut line) {
            Ok(0) | Err(_) => return,
            Ok(_) => {}
        }
        let ended = line.last() == Some(&b'\n');
        if ended {
            line.pop();
            if line.last() == Some(&b'\r') {
                line.pop();
            }
        } else if line.len() > MAX_LINE_BYTES {
            let _ = to.send(Err(format!(
                "wrote a line of more than {MAX_LINE_BYTES} bytes (a line is one message)"
            )));
            return;
        }
        let sent = match String::from_utf8(line) {
            Ok(text) => to.send(Ok(text)),
            Err(e) => {
                let _ = to.send(Err(format!(
                    "wrote a line that is not UTF-8 text (bad byte at {})",
                    e.utf8_error().valid_up_to()
                )));
                return;
            }
        };
        if sent.is_err() {
            return;
        }
    }
}

/// A running child process and its lines.
#[derive(Debug)]
pub struct Child {
    process: std::process::Child,
    /// Whether the child has been reaped: its pid, and so its group's id,
    /// may then be another's, and must not be signalled.
    reaped: bool,
    stdin: Option<BufWriter<ChildStdin>>,
    lines: Receiver<Result<String, String>>,
    stderr: Arc<Mutex<VecDeque<String>>>,
    log: SharedStderr,
}

impl Child {
    /// Starts `words[0]` with the rest as its arguments, in the current
    /// directory.
    pub fn spawn(words: &[String]) -> Result<Self, String> {
        let (program, args) = words
            .split_first()
            .ok_or("an empty command: write exec:PROGRAM ARGS...")?;
        let mut command = Command::new(program);
        command
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        #[cfg(unix)]
        {
            use std::os::unix::process::CommandExt;
            // Its own group, led by itself: what it starts is killed with it.
            command.process_group(0);
        }
        kill_groups_on_interrupt();
        let mut process = command
            .spawn()
            .map_err(|e| format!("cannot start `{program}`: {e}"))?;
        if let Ok(mut groups) = LIVE_GROUPS.lock() {
            groups.push(process.id());
        }
        let stdin = process.stdin.take().map(BufWriter::new);
        let (send, lines) = mpsc::channel();
        if let Some(out) = process.stdout.take() {
            std::thread::spawn(move || send_lines(out, &send));
        }
        let stderr = Arc::new(Mutex::new(VecDeque::new()));
        let log = SharedStderr::default();
        if let Some(err) = process.stderr.take() {
            let (tail, whole) = (Arc::clone(&stderr), Arc::clone(&log));
            std::thread::spawn(move || {
                // In pieces of at most a line's bound: a line without end
                // cannot take the host's memory.
                let mut reader = BufReader::new(err);
                loop {
                    use std::io::Read;
                    let mut piece = Vec::new();
                    let limit = u64::try_from(MAX_LINE_BYTES).unwrap_or(u64::MAX);
                    match (&mut reader).take(limit).read_until(b'\n', &mut piece) {
                        Ok(0) | Err(_) => break,
                        Ok(_) => {}
                    }
                    let text = String::from_utf8_lossy(&piece);
                    let line = text.trim_end_matches(['\n', '\r']).to_string();
                    if let Ok(mut w) = whole.lock() {
                        w.push(&line);
                    }
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
            reaped: false,
            stdin,
            lines,
            stderr,
            log,
        })
    }

    /// Its whole stderr so far, as it is written (up to [`STDERR_KEPT_BYTES`]).
    pub fn stderr_log(&self) -> SharedStderr {
        Arc::clone(&self.log)
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
            Ok(Ok(line)) => Ok(line),
            Ok(Err(why)) => Err(Fault::NotALine(why)),
            Err(RecvTimeoutError::Timeout) => Err(Fault::Silent(limit.as_secs_f64())),
            Err(RecvTimeoutError::Disconnected) => Err(Fault::Gone(self.ended())),
        }
    }

    /// A line the child wrote that nobody has asked for yet, if any.
    pub fn unasked(&self) -> Option<String> {
        self.lines
            .try_recv()
            .ok()
            .map(|l| l.unwrap_or_else(|why| format!("({why})")))
    }

    /// How the child ended, waiting a moment for it (its stdout closed or
    /// its stdin broke, so it is ending or has ended).
    fn ended(&mut self) -> Option<String> {
        let until = Instant::now() + EXIT_GRACE;
        while !self.has_exited() {
            if Instant::now() >= until {
                return None;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        self.end_group()
    }

    /// Whether the child has exited, without reaping it (on unix), so that
    /// its group can still be killed by its id.
    fn has_exited(&mut self) -> bool {
        #[cfg(unix)]
        {
            use nix::sys::wait::{Id, WaitPidFlag, WaitStatus, waitid};
            let flags = WaitPidFlag::WEXITED | WaitPidFlag::WNOHANG | WaitPidFlag::WNOWAIT;
            match i32::try_from(self.process.id()) {
                Ok(pid) => !matches!(
                    waitid(Id::Pid(nix::unistd::Pid::from_raw(pid)), flags),
                    Ok(WaitStatus::StillAlive)
                ),
                Err(_) => true,
            }
        }
        #[cfg(not(unix))]
        {
            !matches!(self.process.try_wait(), Ok(None))
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
    /// exit, then kills it (its whole group); whether it had exited by itself.
    pub fn finish(&mut self, last: &str) -> bool {
        let _ = self.send(last);
        if let Some(mut stdin) = self.stdin.take() {
            let _ = stdin.flush();
        }
        let until = Instant::now() + EXIT_GRACE;
        while !self.has_exited() && Instant::now() < until {
            std::thread::sleep(Duration::from_millis(2));
        }
        let exited = self.reaped || self.has_exited();
        self.end_group();
        exited
    }

    /// Kills the child's whole group (what it started too, even after the
    /// child itself exited: it is not reaped until then) and reaps the
    /// child; how it ended, in words. Once only.
    fn end_group(&mut self) -> Option<String> {
        if self.reaped {
            return None;
        }
        let id = self.process.id();
        kill_group(id);
        let _ = self.process.kill();
        let status = self.process.wait().ok();
        self.reaped = true;
        if let Ok(mut groups) = LIVE_GROUPS.lock() {
            groups.retain(|&g| g != id);
        }
        status.map(describe)
    }
}

impl Drop for Child {
    fn drop(&mut self) {
        self.stdin.take();
        self.end_group();
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
