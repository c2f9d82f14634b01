//! The macros that turn the declarations of `table.rs` into code: one declaration per variable
//! becomes its struct field, its default, its id, its name, value reference, unit, rule and
//! presence. Nothing here names a variable; read `table.rs` for the variables themselves.

/// Number of identifiers given, as a constant expression.
macro_rules! count {
    () => { 0usize };
    ($head:ident $($tail:ident)*) => { 1usize + count!($($tail)*) };
}

/// Calls the presence predicate `$present` (a closure of the declaration) on a configuration.
macro_rules! present {
    ($present:expr, $c:expr) => {{
        let present: fn(&Config) -> bool = $present;
        present($c)
    }};
}

/// Declares the parameters: the struct [`Params`](crate::table::Params) with its `Default`, the
/// id enum [`ParamId`](crate::table::ParamId) and every fact of each parameter as a method of it.
macro_rules! parameters {
    ($(
        $(#[doc = $doc:literal])*
        $id:ident => $field:ident {
            name: $name:literal,
            vr: $vr:literal,
            unit: $unit:literal,
            display: $display:expr,
            default: $default:expr,
            rule: $rule:expr,
            $(narrowed: $narrowed:expr,)?
            variability: $variability:ident,
            present: $present:expr,
            description: $description:literal $(,)?
        }
    )*) => {
        /// Every parameter of every scene. A scene uses a subset; the others keep their defaults
        /// and are never read by the arithmetic of that scene.
        #[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        pub struct Params {
            $( #[doc = $description] $(#[doc = $doc])* pub $field: f64, )*
            /// The reference load, not a variable: the normal force at which the load-scaled
            /// parameters are given (a scene's start value of `F_N`; see
            /// [`Params::set_reference`]).
            pub f_n_ref: f64,
            /// The friction coefficient of the reference load (a scene's start value of `mu`).
            pub mu_ref: f64,
        }

        impl Default for Params {
            /// The declared defaults, which are also the reference load.
            fn default() -> Self {
                let mut p = Params { $( $field: $default, )* f_n_ref: 0.0, mu_ref: 0.0 };
                p.set_reference();
                p
            }
        }

        /// Identifies one parameter, for generic access (scenes, the model description, get
        /// and set by value reference).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum ParamId {
            $( #[doc = $description] $(#[doc = $doc])* $id, )*
        }

        impl ParamId {
            /// Every parameter, in declaration (value reference) order.
            pub const ALL: [ParamId; count!($($id)*)] = [$(ParamId::$id),*];

            /// The variable name.
            pub const fn name(self) -> &'static str {
                match self { $( ParamId::$id => $name, )* }
            }

            /// The value reference.
            pub const fn vr(self) -> u32 {
                match self { $( ParamId::$id => $vr, )* }
            }

            /// The unit, as named in the model description's `UnitDefinitions`.
            pub const fn unit(self) -> &'static str {
                match self { $( ParamId::$id => $unit, )* }
            }

            /// The display unit an importer's GUI may show, if any.
            pub const fn display_unit(self) -> Option<&'static str> {
                match self { $( ParamId::$id => $display, )* }
            }

            /// The model description's `description`.
            pub const fn description(self) -> &'static str {
                match self { $( ParamId::$id => $description, )* }
            }

            /// The accepted range in every scene (see [`Rule`]).
            pub const fn rule(self) -> Rule {
                match self { $( ParamId::$id => $rule, )* }
            }

            /// The accepted range in a scene with this configuration: the rule, narrowed where
            /// the declaration says so.
            pub fn rule_in(self, c: &Config) -> Rule {
                match self {
                    $( ParamId::$id => {
                        let rule = $rule;
                        $( let narrowed: fn(&Config, Rule) -> Rule = $narrowed;
                           let rule = narrowed(c, rule); )?
                        let _ = c;
                        rule
                    } )*
                }
            }

            /// `fixed`, or `tunable` where the parameter may change during the simulation.
            pub const fn variability(self) -> Variability {
                match self { $( ParamId::$id => Variability::$variability, )* }
            }

            /// True when the parameter may change during the simulation.
            pub const fn tunable(self) -> bool {
                matches!(self.variability(), Variability::Tunable)
            }

            /// True when a scene with this configuration has the parameter.
            pub fn present(self, c: &Config) -> bool {
                match self { $( ParamId::$id => present!($present, c), )* }
            }

            pub fn get(self, p: &Params) -> f64 {
                match self { $( ParamId::$id => p.$field, )* }
            }

            pub(super) fn slot(self, p: &mut Params) -> &mut f64 {
                match self { $( ParamId::$id => &mut p.$field, )* }
            }
        }
    };
}

/// Declares the inputs: the struct [`Inputs`](crate::table::Inputs) (their values at one
/// instant) and the id enum [`InputId`](crate::table::InputId) with every fact of each input.
macro_rules! inputs {
    ($(
        $(#[doc = $doc:literal])*
        $id:ident => $field:ident {
            name: $name:literal,
            vr: $vr:literal,
            unit: $unit:literal,
            display: $display:expr,
            rule: $rule:expr,
            present: $present:expr,
            description: $description:literal $(,)?
        }
    )*) => {
        /// The importer's inputs at one instant.
        #[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
        pub struct Inputs {
            $( #[doc = $description] $(#[doc = $doc])* pub $field: f64, )*
        }

        /// Identifies one input, for generic access.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum InputId {
            $( #[doc = $description] $(#[doc = $doc])* $id, )*
        }

        impl InputId {
            /// Every input, in declaration order (the order of input tracks).
            pub const ALL: [InputId; count!($($id)*)] = [$(InputId::$id),*];

            pub const fn name(self) -> &'static str {
                match self { $( InputId::$id => $name, )* }
            }

            pub const fn vr(self) -> u32 {
                match self { $( InputId::$id => $vr, )* }
            }

            pub const fn unit(self) -> &'static str {
                match self { $( InputId::$id => $unit, )* }
            }

            pub const fn display_unit(self) -> Option<&'static str> {
                match self { $( InputId::$id => $display, )* }
            }

            pub const fn description(self) -> &'static str {
                match self { $( InputId::$id => $description, )* }
            }

            /// The accepted range of the input's value.
            pub const fn rule(self) -> Rule {
                match self { $( InputId::$id => $rule, )* }
            }

            /// True when a scene with this configuration has the input.
            pub fn present(self, c: &Config) -> bool {
                match self { $( InputId::$id => present!($present, c), )* }
            }

            /// Position in [`InputId::ALL`].
            pub const fn index(self) -> usize {
                self as usize
            }

            pub fn get(self, i: &Inputs) -> f64 {
                match self { $( InputId::$id => i.$field, )* }
            }

            pub fn slot(self, i: &mut Inputs) -> &mut f64 {
                match self { $( InputId::$id => &mut i.$field, )* }
            }
        }
    };
}

/// Declares the outputs: the struct [`Outputs`](crate::table::Outputs) (everything the contact
/// reports at one instant) and the id enum [`OutputId`](crate::table::OutputId) with every fact
/// of each output.
macro_rules! outputs {
    ($(
        $(#[doc = $doc:literal])*
        $id:ident => $field:ident {
            name: $name:literal,
            vr: $vr:literal,
            unit: $unit:literal,
            display: $display:expr,
            present: $present:expr,
            depends: $depends:ident,
            description: $description:literal $(,)?
        }
    )*) => {
        /// Everything the contact reports at one instant.
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub struct Outputs {
            $( #[doc = $description] $(#[doc = $doc])* pub $field: f64, )*
        }

        /// Identifies one output, for generic access.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum OutputId {
            $( #[doc = $description] $(#[doc = $doc])* $id, )*
        }

        impl OutputId {
            /// Every output, in declaration order (the order of a scene's `outputs`).
            pub const ALL: [OutputId; count!($($id)*)] = [$(OutputId::$id),*];

            pub const fn name(self) -> &'static str {
                match self { $( OutputId::$id => $name, )* }
            }

            pub const fn vr(self) -> u32 {
                match self { $( OutputId::$id => $vr, )* }
            }

            pub const fn unit(self) -> &'static str {
                match self { $( OutputId::$id => $unit, )* }
            }

            pub const fn display_unit(self) -> Option<&'static str> {
                match self { $( OutputId::$id => $display, )* }
            }

            pub const fn description(self) -> &'static str {
                match self { $( OutputId::$id => $description, )* }
            }

            /// True when a scene with this configuration can have the output.
            pub fn present(self, c: &Config) -> bool {
                match self { $( OutputId::$id => present!($present, c), )* }
            }

            /// What the output depends on (see [`Depends`]).
            pub const fn depends(self) -> Depends {
                match self { $( OutputId::$id => Depends::$depends, )* }
            }

            pub fn get(self, o: &Outputs) -> f64 {
                match self { $( OutputId::$id => o.$field, )* }
            }
        }
    };
}

/// Declares a scene's choice key and its values as rows: the enum (one variant per value), and
/// for each value its spelling in a scene file and its name in prose; for the key its name, what
/// the reference says it requires, what it means, and the rule a value outside the set breaks.
/// The scene reader, the scene reference (`docs/scenes.md`) and the documentation pages read
/// these rows; nothing else spells a value.
macro_rules! choices {
    (
        $(#[doc = $doc:literal])*
        $name:ident {
            key: $key:literal,
            requirement: $requirement:literal,
            $(missing: $missing:literal,)?
            $(default: $default:ident,)?
            meaning: $meaning:literal,
            refusal: $refusal:literal,
            values: {$(
                $(#[doc = $vdoc:literal])*
                $v:ident => $word:literal, $title:literal;
            )*}
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum $name {
            $( $(#[doc = $vdoc])* $v, )*
        }

        impl $name {
            /// Every value, in declaration order (the order the reference lists them).
            pub const ALL: [$name; count!($($v)*)] = [$($name::$v),*];

            /// The scene key and its rows.
            pub const KEY: ChoiceKey = ChoiceKey {
                name: $key,
                requirement: $requirement,
                missing: choices!(@option $($missing)?),
                meaning: $meaning,
                refusal: $refusal,
                words: &[$($word),*],
            };

            /// The value when the scene leaves the key out (`None`: the key is required).
            pub const DEFAULT: Option<$name> = choices!(@option $($name::$default)?);

            /// The value as a scene writes it.
            pub const fn word(self) -> &'static str {
                match self { $( $name::$v => $word, )* }
            }

            /// The value's name in prose (summaries, documentation pages).
            pub const fn title(self) -> &'static str {
                match self { $( $name::$v => $title, )* }
            }

            /// The value a scene's word names.
            pub fn from_word(word: &str) -> Option<$name> {
                $name::ALL.into_iter().find(|v| v.word() == word)
            }
        }
    };
    (@option) => { None };
    (@option $x:expr) => { Some($x) };
}

/// Declares the continuous states of Model Exchange, one row per state: the id enum
/// [`StateId`](super::StateId) and every fact of a state and of its derivative as a method.
/// Value references follow the declaration order (301.., derivatives 401..).
macro_rules! states {
    ($(
        $(#[doc = $doc:literal])*
        $id:ident {
            name: $name:literal,
            unit: $unit:literal,
            display: $display:expr,
            description: $description:literal,
            derivative_unit: $dunit:literal,
            derivative_description: $ddescription:literal,
            present: $present:expr,
            derivative_knowns: $knowns:expr $(,)?
        }
    )*) => {
        /// One continuous state of Model Exchange.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum StateId {
            $( #[doc = $description] $(#[doc = $doc])* $id, )*
        }

        impl StateId {
            /// Every state, in declaration (value reference) order.
            pub const ALL: [StateId; count!($($id)*)] = [$(StateId::$id),*];
            pub const COUNT: usize = StateId::ALL.len();

            pub fn name(self) -> &'static str {
                match self { $( StateId::$id => $name, )* }
            }

            /// The derivative's name, `der(<state>)`.
            pub fn derivative_name(self) -> &'static str {
                match self { $( StateId::$id => concat!("der(", $name, ")"), )* }
            }

            pub fn unit(self) -> &'static str {
                match self { $( StateId::$id => $unit, )* }
            }

            pub fn derivative_unit(self) -> &'static str {
                match self { $( StateId::$id => $dunit, )* }
            }

            pub fn display_unit(self) -> Option<&'static str> {
                match self { $( StateId::$id => $display, )* }
            }

            pub fn description(self) -> &'static str {
                match self { $( StateId::$id => $description, )* }
            }

            pub fn derivative_description(self) -> &'static str {
                match self { $( StateId::$id => $ddescription, )* }
            }

            /// True when a scene with this configuration and these outputs has the state.
            pub fn present(self, c: &Config, outputs: &[OutputId]) -> bool {
                match self {
                    $( StateId::$id => {
                        let present: fn(&Config, &[OutputId]) -> bool = $present;
                        present(c, outputs)
                    } )*
                }
            }

            /// The knowns the derivative depends on, before those the scene lacks are dropped
            /// ([`StateId::derivative_dependencies`]).
            fn derivative_knowns(self, c: &Config) -> Vec<Known> {
                match self {
                    $( StateId::$id => {
                        let knowns: fn(&Config) -> Vec<Known> = $knowns;
                        knowns(c)
                    } )*
                }
            }
        }
    };
}

/// Declares the event indicators of Model Exchange, one row per indicator: the id enum
/// [`IndicatorId`](super::IndicatorId) and its facts as methods. Value references follow the
/// declaration order (501..).
macro_rules! indicators {
    ($(
        $(#[doc = $doc:literal])*
        $id:ident {
            name: $name:literal,
            unit: $unit:literal,
            description: $description:literal,
            present: $present:expr,
            knowns: $knowns:expr $(,)?
        }
    )*) => {
        /// One event indicator of Model Exchange (a local variable in FMI 3.0's manner, listed
        /// in FMI 2.0's model description too).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum IndicatorId {
            $( $(#[doc = $doc])* $id, )*
        }

        impl IndicatorId {
            /// Every indicator, in declaration (value reference) order.
            pub const ALL: [IndicatorId; count!($($id)*)] = [$(IndicatorId::$id),*];

            pub fn name(self) -> &'static str {
                match self { $( IndicatorId::$id => $name, )* }
            }

            pub fn unit(self) -> &'static str {
                match self { $( IndicatorId::$id => $unit, )* }
            }

            pub fn description(self) -> &'static str {
                match self { $( IndicatorId::$id => $description, )* }
            }

            /// True when a scene with this configuration has the indicator.
            pub fn present(self, c: &Config) -> bool {
                match self {
                    $( IndicatorId::$id => {
                        let present: fn(&Config) -> bool = $present;
                        present(c)
                    } )*
                }
            }

            /// The knowns the indicator depends on, before those the scene lacks are dropped
            /// ([`IndicatorId::dependencies`]).
            fn knowns(self, c: &Config) -> Vec<Known> {
                match self {
                    $( IndicatorId::$id => {
                        let knowns: fn(&Config) -> Vec<Known> = $knowns;
                        knowns(c)
                    } )*
                }
            }
        }
    };
}
