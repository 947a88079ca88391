//! `corps teleop --stream`: a viewer speaking Foxglove's WebSocket protocol connects while a
//! key script plays in real time, is told the four topics, subscribes, and receives the
//! robot's shapes (sent before it connected, kept for it), the joint frames, the markers and
//! the log's signals as they are computed, in order of the run's time; a client that does not
//! offer the protocol is refused.

use serde_json::Value;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use tungstenite::client::IntoClientRequest;
use tungstenite::Message;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

#[test]
fn a_viewer_receives_the_session_live() {
    let dir = tempfile::tempdir().expect("a directory");
    let mut child = Command::new(env!("CARGO_BIN_EXE_corps"))
        .current_dir(repo(""))
        .args([
            "teleop",
            "--keys",
            "scenarios/teleop/forward_turn.keys",
            "--duration",
            "4",
            "--stream=127.0.0.1:0",
            "-o",
            dir.path().to_str().expect("utf-8"),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("corps runs");
    let mut stderr = BufReader::new(child.stderr.take().expect("stderr"));
    let mut line = String::new();
    let address = loop {
        line.clear();
        assert!(
            stderr.read_line(&mut line).expect("stderr") > 0,
            "no address"
        );
        if let Some(rest) = line.split("streaming on ws://").nth(1) {
            break rest
                .split_whitespace()
                .next()
                .expect("an address")
                .to_string();
        }
    };
    // The rest of stderr, drained so that the command never blocks on it, shown on failure.
    let rest = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut text);
        text
    });
    // Without the subprotocol: refused.
    assert!(tungstenite::connect(format!("ws://{address}")).is_err());
    let mut request = format!("ws://{address}")
        .into_client_request()
        .expect("a request");
    request.headers_mut().insert(
        "Sec-WebSocket-Protocol",
        "foxglove.websocket.v1".parse().expect("a header"),
    );
    let (mut socket, response) = tungstenite::connect(request).expect("connected");
    assert_eq!(
        response.headers()["Sec-WebSocket-Protocol"],
        "foxglove.websocket.v1"
    );
    let text = |m: Message| -> Value {
        serde_json::from_str(m.to_text().expect("a text message")).expect("JSON")
    };
    let info = text(socket.read().expect("server info"));
    assert_eq!(info["op"], "serverInfo");
    let advertise = text(socket.read().expect("advertise"));
    assert_eq!(advertise["op"], "advertise");
    let channels = advertise["channels"].as_array().expect("channels");
    let mut topic_of = BTreeMap::new();
    let mut subscriptions = Vec::new();
    for (k, c) in channels.iter().enumerate() {
        assert_eq!(c["encoding"], "json");
        assert_eq!(c["schemaEncoding"], "jsonschema");
        let id = 100 + k as u64;
        topic_of.insert(id, c["topic"].as_str().expect("a topic").to_string());
        subscriptions.push(serde_json::json!({"id": id, "channelId": c["id"]}));
    }
    let topics: Vec<&str> = topic_of.values().map(String::as_str).collect();
    assert_eq!(topics, ["/tf", "/robot", "/markers", "/signals"]);
    socket
        .send(Message::text(
            serde_json::json!({"op": "subscribe", "subscriptions": subscriptions}).to_string(),
        ))
        .expect("subscribed");
    // Messages per topic: (time in ns, JSON), and the Time frames.
    let mut received: BTreeMap<String, Vec<(u64, Value)>> = BTreeMap::new();
    let mut clock = Vec::new();
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(30) {
        let Ok(message) = socket.read() else { break };
        let Message::Binary(frame) = message else {
            continue;
        };
        match frame[0] {
            1 => {
                let id = u32::from_le_bytes(frame[1..5].try_into().expect("4 bytes"));
                let time = u64::from_le_bytes(frame[5..13].try_into().expect("8 bytes"));
                let json: Value = serde_json::from_slice(&frame[13..]).expect("JSON");
                let topic = topic_of[&u64::from(id)].clone();
                received.entry(topic).or_default().push((time, json));
            }
            2 => clock.push(u64::from_le_bytes(frame[1..9].try_into().expect("8 bytes"))),
            op => panic!("unknown opcode {op}"),
        }
    }
    let status = child.wait().expect("corps ends");
    let stderr = rest.join().expect("stderr");
    assert!(status.success(), "{status}: {stderr}");
    let robot = &received["/robot"];
    assert_eq!(robot.len(), 1, "the robot's shapes, once");
    assert!(!robot[0].1["entities"]
        .as_array()
        .expect("entities")
        .is_empty());
    let tf = &received["/tf"];
    assert!(
        tf.len() > 50,
        "{} frames of /tf over seconds of a 50 Hz view",
        tf.len()
    );
    assert!(tf[0].1["transforms"].as_array().expect("transforms").len() > 10);
    let signals = &received["/signals"];
    assert!(signals.iter().all(|(_, s)| s["com_x"].is_number()));
    assert!(!received["/markers"].is_empty());
    for (topic, messages) in &received {
        assert!(
            messages.windows(2).all(|w| w[0].0 <= w[1].0),
            "{topic}: times go forward"
        );
    }
    assert!(clock.windows(2).all(|w| w[0] < w[1]) && clock.len() > 50);
    // The last view frame is the session's end (4 s), within the view period.
    let last = clock.last().copied().unwrap_or(0) as f64 * 1e-9;
    assert!((last - 4.0).abs() < 0.05, "last time {last} s");
}
