//! What several integration tests share.

use std::sync::OnceLock;

use testbed::reference::MeasuredModels;
use testbed::scenario::Scenario;

/// The paper's scenario and its measured reference, measured once per test
/// binary (and cached between runs).
pub fn paper_reference() -> &'static (Scenario, MeasuredModels) {
    static SETUP: OnceLock<(Scenario, MeasuredModels)> = OnceLock::new();
    SETUP.get_or_init(|| {
        let scenario = Scenario::paper().expect("scenario");
        let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
        let models =
            testbed::reference::measured_models(&scenario, Some(&cache)).expect("measured");
        (scenario, models)
    })
}
