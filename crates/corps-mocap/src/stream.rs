//! A live stream of poses over UDP, and a sender that plays a clip on it in real time.
//!
//! The protocol: one UTF-8 datagram per frame, `TIME V1 V2 … VN` separated by spaces, TIME in
//! seconds since the sender started and the N values the channels of a skeleton both sides
//! know (the HIERARCHY of a BVH file, in its order and units). A datagram not newer than the
//! last one taken, or malformed (a count other than N, a value that is not a finite number,
//! cut at the buffer's size), is skipped and counted, never an error: a live feed goes on. A
//! feed lost for longer than its timeout takes the next whole frame whatever its time (a
//! sender that restarted).

use crate::bvh::Bvh;
use crate::error::{MocapError, Result};
use crate::skeleton::{Pose, Skeleton, Units};
use crate::source::{Feed, MocapSource};
use std::fmt::Write as _;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Largest datagram taken (a datagram filling it is taken as cut and skipped).
const DATAGRAM: usize = 64 * 1024;
/// Datagrams read in one poll at most (a flooding sender cannot stall a tick).
const PER_POLL: usize = 256;

/// Poses received on a UDP socket.
pub struct UdpSource {
    socket: UdpSocket,
    skeleton: Skeleton,
    pose: Pose,
    buffer: Vec<u8>,
    values: Vec<f64>,
    scratch: Vec<f64>,
    /// The sender's time of the pose held, and the poll time it came at.
    last: Option<(f64, f64)>,
    /// No new pose for longer than this (s): the feed still counts as live.
    pub hold: f64,
    /// No new pose for longer than this (s): the feed is lost.
    pub timeout: f64,
    /// Datagrams taken and skipped.
    pub received: usize,
    pub skipped: usize,
}

impl UdpSource {
    /// Listens on `address` (`127.0.0.1:0` picks a free port: see [`UdpSource::address`])
    /// for poses of `skeleton` (the HIERARCHY of a BVH file).
    pub fn bind(address: &str, skeleton: &Bvh, units: Units) -> Result<UdpSource> {
        let error = |e: std::io::Error| MocapError::Stream {
            address: address.to_string(),
            message: e.to_string(),
        };
        let socket = UdpSocket::bind(address).map_err(error)?;
        socket.set_nonblocking(true).map_err(error)?;
        let skeleton = Skeleton::new(skeleton, units);
        Ok(UdpSource {
            socket,
            pose: skeleton.empty_pose(),
            values: vec![0.0; skeleton.channels],
            scratch: vec![0.0; skeleton.channels],
            skeleton,
            buffer: vec![0; DATAGRAM],
            last: None,
            hold: 0.1,
            timeout: 0.5,
            received: 0,
            skipped: 0,
        })
    }

    /// The address it listens on.
    pub fn address(&self) -> Option<SocketAddr> {
        self.socket.local_addr().ok()
    }

    /// Parses one datagram into `scratch`; its time if it is a whole frame.
    fn parse(&mut self, n: usize) -> Option<f64> {
        let text = std::str::from_utf8(&self.buffer[..n]).ok()?;
        let mut words = text.split_ascii_whitespace();
        let time: f64 = words.next()?.parse().ok().filter(|t: &f64| t.is_finite())?;
        let mut count = 0;
        for w in words {
            let v: f64 = w.parse().ok().filter(|v: &f64| v.is_finite())?;
            *self.scratch.get_mut(count)? = v;
            count += 1;
        }
        (count == self.scratch.len()).then_some(time)
    }
}

impl MocapSource for UdpSource {
    fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    fn poll(&mut self, t: f64) -> (&Pose, Feed) {
        // Until WouldBlock (nothing more now), another socket error (the feed then ages) or
        // the poll's share; the newest whole frame is posed once.
        let mut taken = None;
        for _ in 0..PER_POLL {
            let Ok((n, _)) = self.socket.recv_from(&mut self.buffer) else {
                break;
            };
            let timeout = self.timeout;
            let fresh = |time: f64, last: Option<(f64, f64)>| match last {
                None => true,
                Some((before, at)) => time > before || t - at > timeout,
            };
            match (n < self.buffer.len()).then(|| self.parse(n)).flatten() {
                Some(time) if fresh(time, self.last) => {
                    self.values.copy_from_slice(&self.scratch);
                    self.last = Some((time, t));
                    self.received += 1;
                    taken = Some(time);
                }
                _ => self.skipped += 1,
            }
        }
        if let Some(time) = taken {
            self.skeleton.pose_into(&self.values, time, &mut self.pose);
        }
        let feed = match self.last {
            None => Feed::Waiting,
            Some((_, at)) => Feed::aged(t - at, self.hold, self.timeout),
        };
        (&self.pose, feed)
    }
}

/// Plays `bvh` to `to` in real time (`speed` × its rate) until its end
/// or until `stop` is raised; returns the frames sent.
pub fn send_clip(bvh: &Bvh, to: &str, speed: f64, stop: &AtomicBool) -> Result<usize> {
    let error = |e: std::io::Error| MocapError::Stream {
        address: to.to_string(),
        message: e.to_string(),
    };
    if !(speed.is_finite() && speed > 0.0) {
        return Err(MocapError::Stream {
            address: to.to_string(),
            message: format!("speed {speed}: must be > 0"),
        });
    }
    let socket = UdpSocket::bind("127.0.0.1:0")
        .or_else(|_| UdpSocket::bind("[::1]:0"))
        .map_err(error)?;
    socket.connect(to).map_err(error)?;
    let start = Instant::now();
    let mut line = String::with_capacity(bvh.channels * 16);
    for k in 0..bvh.frames() {
        if stop.load(Ordering::Relaxed) {
            return Ok(k);
        }
        let time = k as f64 * bvh.frame_time;
        let Ok(due) = Duration::try_from_secs_f64(time / speed) else {
            return Err(MocapError::Stream {
                address: to.to_string(),
                message: format!("frame {k} at {time} s × speed {speed}: not a time to wait"),
            });
        };
        if let Some(wait) = due.checked_sub(start.elapsed()) {
            std::thread::sleep(wait);
        }
        // Shortest round-trip exponent form: every value short and exact.
        line.clear();
        let _ = write!(line, "{time:e}");
        for v in bvh.frame(k) {
            let _ = write!(line, " {v:e}");
        }
        if line.len() >= DATAGRAM {
            return Err(MocapError::Stream {
                address: to.to_string(),
                message: format!(
                    "frame {k} needs {} bytes, more than a datagram of {DATAGRAM}",
                    line.len()
                ),
            });
        }
        // A receiver not there yet refuses on some systems: the next frame tries again.
        let _ = socket.send(line.as_bytes());
    }
    Ok(bvh.frames())
}
