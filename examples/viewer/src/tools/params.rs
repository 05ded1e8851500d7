//! A tool's parameters, declared once: one [`Param`] per parameter in a table (its script
//! name, its label and widget, how to read it and how to set it). The same table draws the
//! panel's widget ([`widget`]), sets the parameter from a script ([`set`], behind
//! [`Tool::set_parameter`](super::Tool::set_parameter)) and lists the parameters
//! ([`list`], behind [`Tool::parameters`](super::Tool::parameters)). The widget calls the
//! very setter a script calls, so the panel and scripts cannot disagree.
//!
//! The widget's range only bounds the slider; a setter passes the value through to the
//! editing method, whose own checks refuse a value out of range (the error shows in the
//! status line, or fails the script).

use three_d::egui;

use super::{ToolContext, ToolError};

/// Reads a parameter's current value (for the listing and the widget).
pub type Getter<T> = fn(&T) -> serde_json::Value;

/// Sets a parameter from a value (a script's, or the widget's).
pub type Setter<T> = fn(&mut T, &serde_json::Value, &mut ToolContext<'_>) -> Result<(), ToolError>;

/// The widget of a parameter in the panel.
#[derive(Clone, Copy, Debug)]
pub enum Widget {
    /// A slider over `min..=max` (a number).
    Slider {
        /// Left end.
        min: f64,
        /// Right end.
        max: f64,
        /// Logarithmic scale.
        logarithmic: bool,
    },
    /// A drag value over `min..=max`, whole numbers when `integer`.
    Drag {
        /// Smallest value the widget offers.
        min: f64,
        /// Largest value the widget offers.
        max: f64,
        /// Whole numbers only.
        integer: bool,
        /// Change per pixel dragged.
        speed: f64,
    },
    /// Three drag values (a vector `[x, y, z]`).
    Vector {
        /// Change per pixel dragged, as a fraction of the scene's radius when `relative`.
        speed: f64,
        /// Scale the speed by the scene's radius (a translation).
        relative: bool,
    },
    /// A slider over whole numbers whose range the context gives (the levels of the
    /// document's hierarchy); no widget while it gives none.
    Levels(fn(&ToolContext<'_>) -> Option<(f64, f64)>),
    /// A check box (true or false).
    Check,
    /// One of named choices (the getter returns the name).
    Choice(fn() -> Vec<&'static str>),
    /// A button; pressing it sets the parameter to `true` (an action such as "clear").
    Button,
    /// No widget: scripts only (vertex lists and the like), or a read-only value.
    None,
}

/// One parameter of a tool of type `T`.
pub struct Param<T> {
    /// Script name (`{"action": "set", "param": NAME, …}`) and listing name.
    pub name: &'static str,
    /// Label of the widget.
    pub label: &'static str,
    /// The widget.
    pub widget: Widget,
    /// Reads the value; `None` for actions, which are not listed.
    pub get: Option<Getter<T>>,
    /// Sets the value; `None` for read-only values (listed only).
    pub set: Option<Setter<T>>,
}

impl<T> Param<T> {
    /// A parameter with a getter and a setter.
    pub const fn new(
        name: &'static str,
        label: &'static str,
        widget: Widget,
        get: Getter<T>,
        set: Setter<T>,
    ) -> Self {
        Self {
            name,
            label,
            widget,
            get: Some(get),
            set: Some(set),
        }
    }

    /// An action: a button in the panel, `true` from a script; not listed.
    pub const fn action(name: &'static str, label: &'static str, set: Setter<T>) -> Self {
        Self {
            name,
            label,
            widget: Widget::Button,
            get: None,
            set: Some(set),
        }
    }

    /// A value set by scripts only (no widget), listed with `get` when given.
    pub const fn script(name: &'static str, get: Option<Getter<T>>, set: Setter<T>) -> Self {
        Self {
            name,
            label: name,
            widget: Widget::None,
            get,
            set: Some(set),
        }
    }

    /// A read-only value: listed, never set.
    pub const fn info(name: &'static str, get: Getter<T>) -> Self {
        Self {
            name,
            label: name,
            widget: Widget::None,
            get: Some(get),
            set: None,
        }
    }
}

/// A slider widget.
pub const fn slider(min: f64, max: f64) -> Widget {
    Widget::Slider {
        min,
        max,
        logarithmic: false,
    }
}

/// A logarithmic slider widget.
pub const fn log_slider(min: f64, max: f64) -> Widget {
    Widget::Slider {
        min,
        max,
        logarithmic: true,
    }
}

/// A drag value for whole numbers.
pub const fn count(min: f64, max: f64) -> Widget {
    Widget::Drag {
        min,
        max,
        integer: true,
        speed: 0.25,
    }
}

/// A drag value for a number.
pub const fn drag(min: f64, max: f64, speed: f64) -> Widget {
    Widget::Drag {
        min,
        max,
        integer: false,
        speed,
    }
}

/// The names of a table of choices `(value, name)`.
pub fn names<T>(table: &[(T, &'static str)]) -> Vec<&'static str> {
    table.iter().map(|(_, n)| *n).collect()
}

/// The names in `table`, for error messages.
pub fn table_names<T>(table: &[Param<T>]) -> Vec<&'static str> {
    table.iter().map(|p| p.name).collect()
}

/// Sets parameter `name` of `tool` (named `tool_name`) from `value` through `table`.
///
/// # Errors
/// An unknown or read-only parameter; whatever the setter refuses.
pub fn set<T>(
    tool_name: &str,
    table: &[Param<T>],
    tool: &mut T,
    name: &str,
    value: &serde_json::Value,
    ctx: &mut ToolContext<'_>,
) -> Result<(), ToolError> {
    let param = table
        .iter()
        .find(|p| p.name == name)
        .ok_or_else(|| ToolError::unknown_parameter(tool_name, name, &table_names(table)))?;
    let setter = param.set.ok_or_else(|| {
        ToolError::new(format!(
            "parameter {name:?} of tool {tool_name:?} is read-only"
        ))
    })?;
    setter(tool, value, ctx)
}

/// The listed parameters of `tool` and their current values, in table order.
pub fn list<T>(table: &[Param<T>], tool: &T) -> Vec<(&'static str, serde_json::Value)> {
    table
        .iter()
        .filter_map(|p| p.get.map(|get| (p.name, get(tool))))
        .collect()
}

/// Draws the widget of parameter `name` (from `table`); a change goes through the
/// parameter's setter, and an error it returns goes to the status line. Returns the
/// widget's response (`None` for a parameter without a widget or not in the table).
pub fn widget<T>(
    ui: &mut egui::Ui,
    table: &[Param<T>],
    name: &str,
    tool: &mut T,
    ctx: &mut ToolContext<'_>,
) -> Option<egui::Response> {
    let Some(param) = table.iter().find(|p| p.name == name) else {
        ui.colored_label(egui::Color32::RED, format!("no parameter {name:?}"));
        return None;
    };
    let current = param.get.map(|get| get(tool));
    let mut new_value: Option<serde_json::Value> = None;
    let response = match param.widget {
        Widget::Slider {
            min,
            max,
            logarithmic,
        } => {
            let mut x = current.as_ref().and_then(|v| v.as_f64()).unwrap_or(min);
            let r = ui.add(
                egui::Slider::new(&mut x, min..=max)
                    .text(param.label)
                    .logarithmic(logarithmic),
            );
            if r.changed() {
                new_value = Some(x.into());
            }
            r
        }
        Widget::Drag {
            min,
            max,
            integer,
            speed,
        } => {
            let mut x = current.as_ref().and_then(|v| v.as_f64()).unwrap_or(min);
            let r = ui
                .horizontal(|ui| {
                    ui.label(param.label);
                    let mut drag = egui::DragValue::new(&mut x).range(min..=max).speed(speed);
                    if integer {
                        drag = drag.fixed_decimals(0);
                    }
                    ui.add(drag)
                })
                .inner;
            if r.changed() {
                new_value = Some(if integer {
                    (x.round() as i64).into()
                } else {
                    x.into()
                });
            }
            r
        }
        Widget::Vector { speed, relative } => {
            let speed = if relative {
                speed * ctx.view.scene_radius.max(1e-12)
            } else {
                speed
            };
            let mut xyz = [0.0f64; 3];
            if let Some(a) = current.as_ref().and_then(|v| v.as_array()) {
                for (x, v) in xyz.iter_mut().zip(a) {
                    *x = v.as_f64().unwrap_or(0.0);
                }
            }
            let r = ui
                .horizontal(|ui| {
                    ui.label(param.label);
                    let mut r = ui.add(egui::DragValue::new(&mut xyz[0]).speed(speed));
                    for x in &mut xyz[1..] {
                        r = r.union(ui.add(egui::DragValue::new(x).speed(speed)));
                    }
                    r
                })
                .inner;
            if r.changed() {
                new_value = Some(xyz.to_vec().into());
            }
            r
        }
        Widget::Levels(range) => {
            let (min, max) = range(ctx)?;
            let mut x = current.as_ref().and_then(|v| v.as_f64()).unwrap_or(min);
            let r = ui.add(
                egui::Slider::new(&mut x, min..=max)
                    .integer()
                    .text(param.label),
            );
            if r.changed() {
                new_value = Some((x.round() as i64).into());
            }
            r
        }
        Widget::Check => {
            let mut b = current.as_ref().and_then(|v| v.as_bool()).unwrap_or(false);
            let r = ui.checkbox(&mut b, param.label);
            if r.changed() {
                new_value = Some(b.into());
            }
            r
        }
        Widget::Choice(choices) => {
            let selected = current
                .as_ref()
                .and_then(|v| v.as_str())
                .unwrap_or("")
                .to_owned();
            let choices = choices();
            if choices.len() > 4 {
                ui.horizontal(|ui| {
                    ui.label(param.label);
                    egui::ComboBox::from_id_salt(param.name)
                        .selected_text(selected.as_str())
                        .show_ui(ui, |ui| {
                            for choice in choices {
                                if ui.selectable_label(choice == selected, choice).clicked()
                                    && choice != selected
                                {
                                    new_value = Some(choice.into());
                                }
                            }
                        })
                        .response
                })
                .inner
            } else {
                ui.horizontal_wrapped(|ui| {
                    ui.label(param.label);
                    let mut r: Option<egui::Response> = None;
                    for choice in choices {
                        let c = ui.selectable_label(choice == selected, choice);
                        if c.clicked() && choice != selected {
                            new_value = Some(choice.into());
                        }
                        r = Some(match r {
                            Some(r) => r.union(c),
                            None => c,
                        });
                    }
                    r
                })
                .inner
                .unwrap_or_else(|| ui.label(""))
            }
        }
        Widget::Button => {
            let r = ui.button(param.label);
            if r.clicked() {
                new_value = Some(true.into());
            }
            r
        }
        Widget::None => return None,
    };
    if let (Some(value), Some(setter)) = (new_value, param.set) {
        if let Err(e) = setter(tool, &value, ctx) {
            ctx.error(format!("{}: {e}", param.name));
        }
    }
    Some(response)
}

/// Reads a whole, non-negative number (a count, a level).
///
/// # Errors
/// A value that is not a whole number ≥ 0.
pub fn whole(name: &str, value: &serde_json::Value) -> Result<usize, ToolError> {
    match value.as_f64() {
        Some(x) if x >= 0.0 && x.fract() == 0.0 && x <= usize::MAX as f64 => Ok(x as usize),
        _ => Err(ToolError::bad_value(name, "a whole number ≥ 0", value)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::colors::Display;
    use crate::document::Document;
    use crate::tools::{Status, ViewInfo};
    use glam::DVec3;

    /// A tool of two parameters: a flag and an action counting its presses.
    #[derive(Default)]
    struct Toy {
        flag: bool,
        presses: u32,
    }

    const TOY: &[Param<Toy>] = &[
        Param::new(
            "flag",
            "flag",
            Widget::Check,
            |t| t.flag.into(),
            |t, v, _| {
                t.flag = v
                    .as_bool()
                    .ok_or_else(|| ToolError::new("flag: true or false"))?;
                Ok(())
            },
        ),
        Param::action("press", "Press", |t, _, ctx| {
            t.presses += 1;
            ctx.info(format!("pressed {}", t.presses));
            Ok(())
        }),
    ];

    /// Runs one egui frame drawing `name`'s widget with `events`; returns its rectangle.
    fn frame(
        egui: &egui::Context,
        events: Vec<egui::Event>,
        toy: &mut Toy,
        name: &str,
        ctx: &mut ToolContext<'_>,
    ) -> egui::Rect {
        let mut rect = egui::Rect::NOTHING;
        let input = egui::RawInput {
            events,
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(400.0, 300.0),
            )),
            ..Default::default()
        };
        let _ = egui.run_ui(input, |ui| {
            if let Some(r) = widget(ui, TOY, name, toy, ctx) {
                rect = r.rect;
            }
        });
        rect
    }

    fn click_at(p: egui::Pos2) -> Vec<egui::Event> {
        let button = |pressed| egui::Event::PointerButton {
            pos: p,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        };
        vec![egui::Event::PointerMoved(p), button(true), button(false)]
    }

    #[test]
    fn the_widget_goes_through_the_setter_scripts_use() {
        let mut doc = Document::new(halfedge::generators::icosphere(0), None, None);
        let mut display = Display::default();
        let mut status = Status::default();
        let mut ctx = ToolContext {
            doc: &mut doc,
            display: &mut display,
            status: &mut status,
            view: ViewInfo {
                eye: DVec3::Z,
                forward: DVec3::NEG_Z,
                right: DVec3::X,
                up: DVec3::Y,
                scene_radius: 1.0,
            },
            pick: None,
        };
        let egui = egui::Context::default();
        let mut toy = Toy::default();
        for name in ["press", "flag"] {
            let rect = frame(&egui, Vec::new(), &mut toy, name, &mut ctx);
            assert!(rect.is_positive(), "{name} has a widget");
            frame(&egui, click_at(rect.center()), &mut toy, name, &mut ctx);
            frame(&egui, Vec::new(), &mut toy, name, &mut ctx);
        }
        assert_eq!(toy.presses, 1, "the button ran the action's setter");
        assert_eq!(ctx.status.message, "pressed 1");
        assert!(toy.flag, "the check box set the flag through its setter");
        assert_eq!(list(TOY, &toy), [("flag", true.into())]);
        // Scripts reach the same entries.
        set("toy", TOY, &mut toy, "press", &true.into(), &mut ctx).unwrap();
        assert_eq!(toy.presses, 2);
        let e = set("toy", TOY, &mut toy, "nope", &1.into(), &mut ctx).unwrap_err();
        assert!(e.0.contains("flag, press"), "{e}");
    }
}
