//! stub
use super::{SharedLabels, Tool, ToolContext};
use three_d::egui;
/// stub
pub struct FfdTool {
    _s: SharedLabels,
}
impl FfdTool {
    /// stub
    pub fn new(s: SharedLabels) -> Self {
        Self { _s: s }
    }
}
impl Tool for FfdTool {
    fn name(&self) -> &str {
        "FFD"
    }
    fn description(&self) -> &str {
        ""
    }
    fn ui(&mut self, _ui: &mut egui::Ui, _ctx: &mut ToolContext<'_>) {}
}
