//! The log categories of every FMU: listed in the model description (`LogCategories`) and on
//! its documentation page, and the categories the instance logs under.

/// A log category.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    Events = 0,
    StatusWarning = 1,
    StatusError = 2,
    All = 3,
}

impl Category {
    pub const ALL: [Category; 4] = [
        Category::Events,
        Category::StatusWarning,
        Category::StatusError,
        Category::All,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Category::Events => "logEvents",
            Category::StatusWarning => "logStatusWarning",
            Category::StatusError => "logStatusError",
            Category::All => "logAll",
        }
    }

    pub fn description(self) -> &'static str {
        match self {
            Category::Events => "Instance life cycle and solver events (instantiation, initialization, reset, state save/restore)",
            Category::StatusWarning => "Calls that returned fmi2Warning",
            Category::StatusError => "Calls that returned fmi2Error or fmi2Discard, naming the variable and the rule",
            Category::All => "Every message, including per-call traces",
        }
    }

    pub fn from_name(s: &str) -> Option<Category> {
        Category::ALL.into_iter().find(|c| c.name() == s)
    }
}
