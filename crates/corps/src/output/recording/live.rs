//! A live stream of the scene to Foxglove over its WebSocket protocol (`foxglove.websocket.v1`,
//! github.com/foxglove/ws-protocol): a server thread accepts viewers, advertises the scene's
//! topics as JSON channels, sends each subscriber its messages (binary Message Data frames:
//! opcode 1, subscription id, time in ns, JSON) and the run's time (Time frames, opcode 2),
//! so the viewer's clock is the controlled time. The robot's shapes, sent once, are kept and
//! given to every viewer that subscribes later.
//!
//! The control loop never waits for the network: messages go through a bounded queue and
//! are dropped, counted, when it is full. Each viewer's unsent frames wait in a buffer of at
//! most [`VIEWER_BUFFER`] bytes; a viewer too slow to empty it loses the frames beyond.

use super::topics::{Publish, Topic};
use anyhow::{Context, Result};
use serde_json::{json, Value};
use std::io::ErrorKind;
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;
use tungstenite::handshake::server::{Callback, ErrorResponse, Request, Response};
use tungstenite::http::{header::SEC_WEBSOCKET_PROTOCOL, HeaderValue, StatusCode};
use tungstenite::protocol::WebSocketConfig;
use tungstenite::{Message, WebSocket};

/// The subprotocol of Foxglove's WebSocket protocol.
pub const SUBPROTOCOL: &str = "foxglove.websocket.v1";
/// Messages waiting for the server thread before new ones are dropped.
const QUEUE: usize = 1024;
/// A viewer's unsent bytes at most: the robot's shapes (its meshes, a few MB) and some
/// seconds of the scene.
pub const VIEWER_BUFFER: usize = 64 << 20;
/// How long the end of a stream may take to reach a viewer.
const CLOSE_TIMEOUT: Duration = Duration::from_secs(2);

/// A message for the viewers.
struct Outgoing {
    topic: Topic,
    time_ns: u64,
    json: Arc<Vec<u8>>,
}

/// The scene streamed live on a TCP address.
pub struct LiveStream {
    queue: Option<SyncSender<Outgoing>>,
    server: Option<JoinHandle<()>>,
    address: SocketAddr,
    dropped: Arc<AtomicU64>,
}

impl LiveStream {
    /// Listens on `address` (`host:port`; port 0 picks a free one).
    pub fn bind(address: &str) -> Result<Self> {
        let listener = TcpListener::bind(address)
            .with_context(|| format!("--stream: listening on {address}"))?;
        listener.set_nonblocking(true)?;
        let address = listener.local_addr()?;
        let (queue, messages) = sync_channel(QUEUE);
        let server = std::thread::Builder::new()
            .name("corps-stream".into())
            .spawn(move || serve(listener, messages))?;
        Ok(Self {
            queue: Some(queue),
            server: Some(server),
            address,
            dropped: Arc::new(AtomicU64::new(0)),
        })
    }

    /// Where viewers connect.
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// Messages dropped because the queue was full.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

impl Publish for LiveStream {
    fn publish(&mut self, topic: Topic, t: f64, json: Vec<u8>) -> Result<()> {
        let Some(queue) = &self.queue else {
            return Ok(());
        };
        let message = Outgoing {
            topic,
            time_ns: (t.max(0.0) * 1e9).round() as u64,
            json: Arc::new(json),
        };
        match queue.try_send(message) {
            Ok(()) => {}
            Err(TrySendError::Full(_)) => {
                self.dropped.fetch_add(1, Ordering::Relaxed);
            }
            // The server thread ended (it only does when the queue closes): nothing to do.
            Err(TrySendError::Disconnected(_)) => {}
        }
        Ok(())
    }

    /// Closes the connections (by dropping the stream: [`Drop`] ends the server).
    fn finish(self: Box<Self>) -> Result<Option<PathBuf>> {
        drop(self);
        Ok(None)
    }
}

impl Drop for LiveStream {
    /// Closes the queue, which ends the server thread after it has sent what it holds, and
    /// waits for it.
    fn drop(&mut self) {
        self.queue = None;
        if let Some(server) = self.server.take() {
            let _ = server.join();
        }
    }
}

/// The server thread: accepts viewers, forwards the queue's messages, reads subscriptions;
/// ends, closing every connection, when the queue closes.
fn serve(listener: TcpListener, messages: Receiver<Outgoing>) {
    let mut viewers: Vec<Viewer> = Vec::new();
    let mut robot: Option<Outgoing> = None;
    loop {
        while let Ok((stream, _)) = listener.accept() {
            if let Some(v) = Viewer::open(stream) {
                viewers.push(v);
            }
        }
        let mut forward = |m: Outgoing, viewers: &mut Vec<Viewer>| {
            for v in viewers.iter_mut() {
                v.send(&m);
            }
            if m.topic == Topic::Robot {
                robot = Some(m);
            }
        };
        match messages.recv_timeout(Duration::from_millis(10)) {
            Ok(m) => {
                forward(m, &mut viewers);
                while let Ok(m) = messages.try_recv() {
                    forward(m, &mut viewers);
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        viewers.retain_mut(|v| v.poll(robot.as_ref()));
    }
    // The last frames and the close, waited for (each viewer at most CLOSE_TIMEOUT).
    for mut v in viewers {
        let stream = v.socket.get_mut();
        if stream.set_nonblocking(false).is_err()
            || stream.set_write_timeout(Some(CLOSE_TIMEOUT)).is_err()
        {
            continue;
        }
        let _ = v.socket.close(None);
        let _ = v.socket.flush();
    }
}

/// One connected viewer and its subscriptions (id, topic).
struct Viewer {
    socket: WebSocket<TcpStream>,
    subscriptions: Vec<(u32, Topic)>,
    alive: bool,
}

impl Viewer {
    /// The handshake (the viewer must offer [`SUBPROTOCOL`]), then the server's info and the
    /// channels. None when the handshake fails.
    fn open(stream: TcpStream) -> Option<Self> {
        stream.set_nonblocking(false).ok()?;
        stream.set_read_timeout(Some(Duration::from_secs(2))).ok()?;
        let config = WebSocketConfig::default().max_write_buffer_size(VIEWER_BUFFER);
        let mut socket =
            tungstenite::accept_hdr_with_config(stream, OffersSubprotocol, Some(config)).ok()?;
        socket.get_mut().set_nonblocking(true).ok()?;
        let info = json!({
            "op": "serverInfo", "name": "corps", "capabilities": ["time"],
            "supportedEncodings": [], "metadata": {},
        });
        let channels: Vec<Value> = (Topic::ALL.iter())
            .map(|t| {
                json!({"id": t.index() + 1, "topic": t.name(), "encoding": "json",
                       "schemaName": t.schema_name(), "schema": t.schema(),
                       "schemaEncoding": "jsonschema"})
            })
            .collect();
        let mut viewer = Self {
            socket,
            subscriptions: Vec::new(),
            alive: true,
        };
        viewer.write(Message::text(info.to_string()));
        viewer.write(Message::text(
            json!({"op": "advertise", "channels": channels}).to_string(),
        ));
        viewer.alive.then_some(viewer)
    }

    fn write(&mut self, message: Message) {
        match self.socket.write(message) {
            Ok(()) => {}
            // A full buffer (a slow viewer) drops the frame; the connection stays.
            Err(tungstenite::Error::WriteBufferFull(_)) => {}
            // Buffered: sent by a later flush.
            Err(tungstenite::Error::Io(e)) if e.kind() == ErrorKind::WouldBlock => {}
            Err(_) => self.alive = false,
        }
    }

    /// `m` to this viewer's subscriptions of its topic; the run's time with each view frame.
    fn send(&mut self, m: &Outgoing) {
        if m.topic == Topic::Tf {
            let mut time = Vec::with_capacity(9);
            time.push(2u8);
            time.extend_from_slice(&m.time_ns.to_le_bytes());
            self.write(Message::binary(time));
        }
        let ids: Vec<u32> = (self.subscriptions.iter())
            .filter(|(_, t)| *t == m.topic)
            .map(|(id, _)| *id)
            .collect();
        for id in ids {
            self.write(Message::binary(data_frame(id, m)));
        }
    }

    /// Reads the viewer's requests and flushes; false once the viewer is gone.
    fn poll(&mut self, robot: Option<&Outgoing>) -> bool {
        loop {
            match self.socket.read() {
                Ok(Message::Text(text)) => self.request(text.as_str(), robot),
                Ok(Message::Close(_)) => return false,
                Ok(_) => {}
                Err(tungstenite::Error::Io(e)) if e.kind() == ErrorKind::WouldBlock => break,
                Err(_) => return false,
            }
        }
        match self.socket.flush() {
            Ok(()) => {}
            Err(tungstenite::Error::Io(e)) if e.kind() == ErrorKind::WouldBlock => {}
            Err(_) => self.alive = false,
        }
        self.alive
    }

    /// `subscribe` and `unsubscribe`; other requests are not offered and are ignored.
    fn request(&mut self, text: &str, robot: Option<&Outgoing>) {
        let Ok(request) = serde_json::from_str::<Value>(text) else {
            return;
        };
        match request["op"].as_str() {
            Some("subscribe") => {
                for s in request["subscriptions"].as_array().into_iter().flatten() {
                    let (Some(id), Some(channel)) = (s["id"].as_u64(), s["channelId"].as_u64())
                    else {
                        continue;
                    };
                    let Some(topic) = (channel as usize)
                        .checked_sub(1)
                        .and_then(|k| Topic::ALL.get(k))
                    else {
                        continue;
                    };
                    let id = id as u32;
                    if self.subscriptions.iter().any(|(s, _)| *s == id) {
                        continue;
                    }
                    self.subscriptions.push((id, *topic));
                    if let Some(r) = robot.filter(|_| *topic == Topic::Robot) {
                        self.write(Message::binary(data_frame(id, r)));
                    }
                }
            }
            Some("unsubscribe") => {
                let gone: Vec<u64> = (request["subscriptionIds"].as_array().into_iter())
                    .flatten()
                    .filter_map(Value::as_u64)
                    .collect();
                self.subscriptions
                    .retain(|(id, _)| !gone.contains(&u64::from(*id)));
            }
            _ => {}
        }
    }
}

/// The handshake's check: the viewer must offer [`SUBPROTOCOL`], which the answer selects.
struct OffersSubprotocol;

impl Callback for OffersSubprotocol {
    fn on_request(
        self,
        request: &Request,
        mut response: Response,
    ) -> Result<Response, ErrorResponse> {
        let offered = request
            .headers()
            .get_all(SEC_WEBSOCKET_PROTOCOL)
            .iter()
            .filter_map(|h| h.to_str().ok())
            .flat_map(|h| h.split(','))
            .any(|p| p.trim() == SUBPROTOCOL);
        if !offered {
            let mut refusal = ErrorResponse::new(Some(format!(
                "corps streams with the {SUBPROTOCOL} subprotocol only"
            )));
            *refusal.status_mut() = StatusCode::BAD_REQUEST;
            return Err(refusal);
        }
        response.headers_mut().insert(
            SEC_WEBSOCKET_PROTOCOL,
            HeaderValue::from_static(SUBPROTOCOL),
        );
        Ok(response)
    }
}

/// A Message Data frame: opcode 1, subscription id and time (little-endian), the JSON.
fn data_frame(subscription: u32, m: &Outgoing) -> Vec<u8> {
    let mut frame = Vec::with_capacity(13 + m.json.len());
    frame.push(1u8);
    frame.extend_from_slice(&subscription.to_le_bytes());
    frame.extend_from_slice(&m.time_ns.to_le_bytes());
    frame.extend_from_slice(&m.json);
    frame
}
