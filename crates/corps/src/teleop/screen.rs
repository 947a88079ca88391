//! The terminal display of `corps teleop` (ratatui): the commanded and achieved velocities,
//! their recent history as a chart, the steps, the pose and the controller's time; keys
//! steer the walk as they are pressed.

use super::keys::{self, KeyAction, HELP};
use super::status::{Status, VELOCITY_WINDOW};
use corps_scenario::teleop::VelocityPad;
use corps_scenario::velocity_walk::LiveVelocity;
use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind, KeyModifiers};
use ratatui::layout::{Constraint, Layout};
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::Line;
use ratatui::widgets::{Axis, Block, Chart, Dataset, GraphType, Paragraph};
use ratatui::Frame;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Runs the display until `finished` is raised (the run ended: duration, fall or quit); keys
/// update `pad` and `input`, `q`/Esc/Ctrl-C raise `quit`. The terminal is restored on return
/// and on a panic.
pub fn show(
    title: &str,
    shared: &Mutex<Status>,
    input: &Arc<LiveVelocity>,
    mut pad: VelocityPad,
    quit: &AtomicBool,
    finished: &AtomicBool,
) -> anyhow::Result<()> {
    let mut terminal = ratatui::try_init()?;
    let result = (|| -> anyhow::Result<()> {
        while !finished.load(Ordering::SeqCst) {
            let status = shared.lock().map(|s| s.clone()).unwrap_or_default();
            terminal.draw(|f| draw(f, title, &status))?;
            if !event::poll(Duration::from_millis(50))? {
                continue;
            }
            let Event::Key(k) = event::read()? else {
                continue;
            };
            if k.kind != KeyEventKind::Press {
                continue;
            }
            let action = match k.code {
                KeyCode::Char('c') if k.modifiers.contains(KeyModifiers::CONTROL) => {
                    Some(KeyAction::Quit)
                }
                KeyCode::Esc => Some(KeyAction::Quit),
                KeyCode::Char(c) => keys::action(c),
                _ => None,
            };
            match action {
                Some(KeyAction::Pad(a)) => input.set(pad.apply(a)),
                Some(KeyAction::Quit) => {
                    // A zero command first, as seed 002's script publishes on quit.
                    input.set(Default::default());
                    quit.store(true, Ordering::SeqCst);
                }
                None => {}
            }
        }
        Ok(())
    })();
    ratatui::restore();
    result
}

fn draw(f: &mut Frame, title: &str, s: &Status) {
    let [head, body, help] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Min(10),
        Constraint::Length(1),
    ])
    .areas(f.area());
    f.render_widget(
        Paragraph::new(format!(
            "corps teleop  {title}   t = {:.1} s   ×{:.2} real time",
            s.t, s.realtime_factor
        ))
        .style(Style::new().fg(Color::Cyan)),
        head,
    );
    let [numbers, chart] =
        Layout::horizontal([Constraint::Length(44), Constraint::Min(30)]).areas(body);
    let (distance, heading) = s.travelled();
    let c = s.commanded;
    let a = s.achieved;
    let lines = vec![
        Line::from("              commanded   achieved"),
        Line::from(format!("v_x  (m/s)    {:>9.2}  {:>9.3}", c.vx, a[0])),
        Line::from(format!("v_y  (m/s)    {:>9.2}  {:>9.3}", c.vy, a[1])),
        Line::from(format!("ω  (rad/s)    {:>9.2}  {:>9.3}", c.yaw_rate, a[2])),
        Line::from(format!(
            "  (achieved: mean over the last {VELOCITY_WINDOW} s)"
        )),
        Line::from(""),
        Line::from(format!("steps         {}", s.steps)),
        Line::from(format!(
            "base          x {:.3} m  y {:.3} m",
            s.pose.x, s.pose.y
        )),
        Line::from(format!("              yaw {:.1}°", s.pose.yaw.to_degrees())),
        Line::from(format!(
            "travelled     {distance:.3} m, turned {:.1}°",
            heading.to_degrees()
        )),
        Line::from(""),
        Line::from(format!(
            "controller    {:.0} µs/tick (max {:.0})",
            s.tick_us, s.tick_us_max
        )),
    ];
    f.render_widget(
        Paragraph::new(lines).block(Block::bordered().title(" velocity ")),
        numbers,
    );
    draw_chart(f, chart, s);
    f.render_widget(
        Paragraph::new(HELP).style(Style::new().fg(Color::Yellow)),
        help,
    );
}

fn draw_chart(f: &mut Frame, area: ratatui::layout::Rect, s: &Status) {
    let series = |k: usize| -> Vec<(f64, f64)> { s.history.iter().map(|h| (h[0], h[k])).collect() };
    let (cx, ax, cy, ay) = (series(1), series(2), series(3), series(4));
    let t1 = s.t.max(1.0);
    let t0 = s.history.first().map_or(0.0, |h| h[0]).min(t1 - 1.0);
    let datasets = vec![
        line("v_x commanded", Color::Blue, &cx),
        line("v_x achieved", Color::LightBlue, &ax),
        line("v_y commanded", Color::Red, &cy),
        line("v_y achieved", Color::LightRed, &ay),
    ];
    let chart = Chart::new(datasets)
        .block(Block::bordered().title(" velocity (m/s) over time (s) "))
        .x_axis(
            Axis::default()
                .bounds([t0, t1])
                .labels([format!("{t0:.0}"), format!("{t1:.0}")]),
        )
        .y_axis(
            Axis::default()
                .bounds([-0.35, 0.35])
                .labels(["-0.3", "0", "0.3"]),
        );
    f.render_widget(chart, area);
}

fn line<'a>(name: &'a str, color: Color, data: &'a [(f64, f64)]) -> Dataset<'a> {
    Dataset::default()
        .name(name)
        .marker(Marker::Braille)
        .graph_type(GraphType::Line)
        .style(Style::new().fg(color))
        .data(data)
}
