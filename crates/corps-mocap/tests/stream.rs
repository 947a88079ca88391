//! The live stream on the loopback: a clip sent in real time arrives as the clip's poses; a
//! malformed datagram is skipped and counted; a stream that stops holds its last pose, then is
//! lost; polling never blocks.

use corps_mocap::bvh::Bvh;
use corps_mocap::skeleton::{Skeleton, Units};
use corps_mocap::source::{Feed, MocapSource};
use corps_mocap::stream::{send_clip, UdpSource};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// A clip written here: a root swaying and an arm turning, 40 frames at 100 Hz.
fn clip() -> Bvh {
    let mut text = String::from(
        "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT Arm\n {\n  OFFSET 10 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 20 0 0\n  }\n }\n}\nMOTION\nFrames: 40\nFrame Time: 0.01\n",
    );
    for k in 0..40 {
        let s = k as f64 * 0.1;
        text += &format!("{} 90 0 {} 0 0 {} {} 0\n", s.sin(), s, 3.0 * s, -s);
    }
    Bvh::parse(&text, "sway.bvh").unwrap()
}

#[test]
fn a_clip_sent_in_real_time_arrives_and_a_stopped_stream_is_held_then_lost() {
    let bvh = clip();
    let mut source = UdpSource::bind("127.0.0.1:0", &bvh, Units::default()).unwrap();
    let address = source.address().unwrap().to_string();
    let skeleton = Skeleton::new(&bvh, Units::default());
    // A malformed datagram first: skipped, counted.
    let junk = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    junk.send_to(b"0.5 1 2 three", &address).unwrap();
    let sender = {
        let bvh = bvh.clone();
        let address = address.clone();
        std::thread::spawn(move || send_clip(&bvh, &address, 1.0, &AtomicBool::new(false)))
    };
    let start = Instant::now();
    let mut live = 0;
    let mut slowest = Duration::ZERO;
    while !sender.is_finished() || start.elapsed() < Duration::from_millis(450) {
        let t = start.elapsed().as_secs_f64();
        let before = Instant::now();
        let (pose, feed) = source.poll(t);
        slowest = slowest.max(before.elapsed());
        if feed == Feed::Live {
            live += 1;
            // The pose is the clip's frame at the sender's time.
            let k = (pose.time / bvh.frame_time).round() as usize;
            let expect = skeleton.pose(bvh.frame(k), pose.time);
            assert_eq!(pose.world, expect.world);
        }
        std::thread::sleep(Duration::from_millis(1));
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "the stream never ended"
        );
    }
    assert_eq!(sender.join().unwrap().unwrap(), 40);
    println!(
        "received {}, skipped {}, live polls {live}, slowest poll {slowest:?}",
        source.received, source.skipped
    );
    assert!(
        source.received >= 30,
        "{} of 40 frames arrived",
        source.received
    );
    assert_eq!(source.skipped, 1);
    assert!(
        slowest < Duration::from_millis(20),
        "a poll took {slowest:?}"
    );
    // The stream stopped: the last pose is held, then the feed is lost.
    let t = start.elapsed().as_secs_f64();
    let last = skeleton.pose(bvh.frame(39), 0.39);
    let (pose, feed) = source.poll(t + source.hold + 0.05);
    assert!(matches!(feed, Feed::Holding { .. }), "{feed:?}");
    assert_eq!(pose.world, last.world);
    let (pose, feed) = source.poll(t + source.timeout + 0.05);
    assert_eq!(feed, Feed::Lost);
    assert_eq!(pose.world, last.world);
}

#[test]
fn a_source_with_nothing_received_waits() {
    let bvh = clip();
    let mut source = UdpSource::bind("127.0.0.1:0", &bvh, Units::default()).unwrap();
    assert_eq!(source.poll(0.0).1, Feed::Waiting);
    assert_eq!(source.poll(5.0).1, Feed::Waiting);
}

#[test]
fn a_sender_that_restarts_is_taken_again_once_the_feed_is_lost() {
    let bvh = clip();
    let mut source = UdpSource::bind("127.0.0.1:0", &bvh, Units::default()).unwrap();
    let address = source.address().unwrap().to_string();
    let sender = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    let frame = |time: f64, k: usize| {
        let mut line = format!("{time:e}");
        for v in bvh.frame(k) {
            line += &format!(" {v:e}");
        }
        line
    };
    let wait_for = |source: &mut UdpSource, t: f64, n: usize| {
        let start = Instant::now();
        while source.received < n && start.elapsed() < Duration::from_secs(5) {
            source.poll(t);
            std::thread::sleep(Duration::from_millis(1));
        }
    };
    // A frame far in the future, then the sender restarts from 0.
    sender.send_to(frame(1e6, 3).as_bytes(), &address).unwrap();
    wait_for(&mut source, 0.0, 1);
    sender.send_to(frame(0.0, 5).as_bytes(), &address).unwrap();
    std::thread::sleep(Duration::from_millis(50));
    // Not newer and the feed still live: skipped.
    assert_eq!(source.poll(0.1).1, Feed::Live);
    assert_eq!((source.received, source.skipped), (1, 1));
    // Lost: the restarted sender's next frame is taken.
    assert_eq!(source.poll(1.0).1, Feed::Lost);
    sender.send_to(frame(0.01, 6).as_bytes(), &address).unwrap();
    wait_for(&mut source, 1.0, 2);
    let (pose, feed) = source.poll(1.0);
    assert_eq!(feed, Feed::Live);
    assert_eq!(pose.time, 0.01);
}
