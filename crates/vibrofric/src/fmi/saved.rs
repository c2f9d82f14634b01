//! Saved states (`fmi2FMUstate`) and their bytes.
//!
//! A state is the instance's [`Staged`] values and the simulator's snapshot, both plain serde
//! structs, encoded with postcard (a compact, stable binary serde format) inside a small frame:
//!
//! ```text
//! magic (16 bytes) | format version (u32 LE) | payload length (u32 LE) | postcard payload | FNV-1a-64 of all before (u64 LE)
//! ```
//!
//! Numbers are `f64` bit patterns, so a round trip is exact. Trailing zero bytes (a buffer
//! larger than needed) are accepted. The bytes are untrusted input: every field is checked as
//! the call that sets it checks it, and the simulator checks its snapshot when it restores.

use serde::{Deserialize, Serialize};

use super::staging::Staged;
use super::state::{Interface, State};
use crate::model::{self, ContactState, InputId};
use crate::table::number;
use crate::table::ParamId;
use crate::table::{StringValues, StringVar};

/// A saved FMU state: the state machine's state, the staged values and the simulator's
/// complete state. Restoring it, also into another instance of the same FMU or after
/// serialization, continues bit for bit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FmuState {
    /// The GUID of the FMU the state was taken from.
    pub guid: String,
    /// The interface of the instance that saved it: it restores only into the same.
    pub interface: Interface,
    /// The standard's edition of the instance that saved it ("FMI 2.0", "FMI 3.0").
    pub edition: String,
    pub staged: Staged,
    /// The simulator's state, once it exists.
    pub sim: Option<ContactState>,
    /// A string scene's values and simulator state.
    pub string: Option<StringSaved>,
}

/// The string's part of a saved state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StringSaved {
    pub values: StringValues,
    pub derivs: Vec<(StringVar, u32, f64)>,
    /// The simulator's state ([`crate::model::string::StringSimulator::save`]), once it
    /// exists.
    pub sim: Option<Vec<f64>>,
}

const MAGIC: &[u8; 16] = b"vibrofric-state\0";
/// 7: with a string scene's part. 6: with the interface and the standard's edition of the instance that saved it (5: Model
/// Exchange's event-indicator sides; 4: postcard payload with the contact's named state; 3:
/// hand-written layout).
const FORMAT_VERSION: u32 = 7;

/// FNV-1a, 64 bit: detects a corrupted or truncated byte string.
fn checksum(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| {
        (h ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The bytes of a state.
pub fn encode(s: &FmuState) -> Vec<u8> {
    // A struct of numbers, strings, options and vectors always serializes.
    let payload = postcard::to_allocvec(s).unwrap_or_default();
    let mut b = Vec::with_capacity(payload.len() + 32);
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    b.extend_from_slice(&payload);
    let sum = checksum(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// The bytes from `at`, `n` of them, or where the string ends.
fn take(bytes: &[u8], at: usize, n: usize) -> Result<&[u8], String> {
    at.checked_add(n)
        .and_then(|end| bytes.get(at..end))
        .ok_or_else(|| {
            format!(
                "serialized state truncated at byte {} of {}",
                at.min(bytes.len()),
                bytes.len()
            )
        })
}

fn u32_at(bytes: &[u8], at: usize) -> Result<u32, String> {
    let mut a = [0; 4];
    a.copy_from_slice(take(bytes, at, 4)?);
    Ok(u32::from_le_bytes(a))
}

/// Reads what [`encode`] wrote and checks every field.
pub fn decode(bytes: &[u8]) -> Result<FmuState, String> {
    if take(bytes, 0, MAGIC.len()).ok() != Some(&MAGIC[..]) {
        return Err("not a serialized vibrofric FMU state (bad magic)".into());
    }
    let version = u32_at(bytes, 16)?;
    if version != FORMAT_VERSION {
        return Err(format!(
            "serialized state has format version {version}, this FMU reads version {FORMAT_VERSION}"
        ));
    }
    let len = u32_at(bytes, 20)? as usize;
    let payload = take(bytes, 24, len)?;
    let end = 24 + len;
    let mut sum = [0; 8];
    sum.copy_from_slice(take(bytes, end, 8)?);
    if u64::from_le_bytes(sum) != checksum(&bytes[..end]) {
        return Err("checksum mismatch: the serialized state is corrupted".into());
    }
    if bytes[end + 8..].iter().any(|&x| x != 0) {
        return Err(format!(
            "{} unexpected bytes after the serialized state",
            bytes.len() - end - 8
        ));
    }
    // A crafted length cannot allocate much: postcard checks a string's length against the
    // bytes left, and serde caps a vector's preallocation (1 MiB) whatever length it reads;
    // bytes left over after the state are refused below.
    let (s, rest): (FmuState, &[u8]) = postcard::take_from_bytes(payload)
        .map_err(|e| format!("the serialized state's payload does not read: {e}"))?;
    if !rest.is_empty() {
        return Err(format!(
            "{} unexpected bytes after the serialized state's payload",
            rest.len()
        ));
    }
    check(&s)?;
    Ok(s)
}

/// Untrusted input: every field checked as the calls that set it check it.
fn check(s: &FmuState) -> Result<(), String> {
    let st = &s.staged;
    for id in ParamId::ALL {
        id.check(id.get(&st.params))
            .map_err(|e| format!("serialized parameter {e}"))?;
    }
    for id in InputId::ALL {
        let x = id.get(&st.inputs);
        if !id.rule().holds(x) {
            return Err(format!(
                "serialized input {} = {x}: {}",
                id.name(),
                id.rule().text(x, id.unit())
            ));
        }
    }
    for (id, d) in InputId::ALL.iter().zip(st.derivs) {
        if let Some(d) = d {
            if !(d.is_finite() && d.abs() <= model::MAX_INPUT_RATE) {
                return Err(format!(
                    "serialized derivative of {} = {}: must be finite and at most {} in magnitude",
                    id.name(),
                    number(d),
                    number(model::MAX_INPUT_RATE)
                ));
            }
        }
    }
    let start_time = st.start_time;
    if !start_time.is_finite() {
        return Err(format!(
            "serialized startTime = {start_time}: must be finite"
        ));
    }
    if let Some(t) = st.tolerance {
        let (lo, hi) = model::TOLERANCE_RANGE;
        if !(lo..=hi).contains(&t) {
            return Err(format!(
                "serialized tolerance = {}: must be in [{}, {}]",
                number(t),
                number(lo),
                number(hi)
            ));
        }
    }
    if let Some(t) = st.stop_time {
        if !(t.is_finite() && t >= start_time) {
            return Err(format!(
                "serialized stopTime = {t}: must be finite and >= startTime = {start_time}"
            ));
        }
    }
    use State as S;
    if !["FMI 2.0", "FMI 3.0"].contains(&s.edition.as_str()) {
        return Err(format!(
            "serialized edition \"{}\": must be \"FMI 2.0\" or \"FMI 3.0\"",
            s.edition
        ));
    }
    let foreign = match s.interface {
        Interface::CoSimulation => matches!(st.state, S::EventMode | S::ContinuousTimeMode),
        Interface::ModelExchange => matches!(st.state, S::StepComplete | S::StepFailed),
    };
    if foreign {
        return Err(format!(
            "serialized state machine state {} is not a state of {}",
            st.state.name(),
            s.interface.name()
        ));
    }
    // A string's simulator state is in its part.
    let has_sim = s.sim.is_some() || s.string.as_ref().is_some_and(|p| p.sim.is_some());
    match (st.state, has_sim) {
        (S::Fatal, _) => Err("serialized state machine state Fatal cannot be restored".into()),
        (
            S::StepComplete | S::StepFailed | S::Terminated | S::EventMode | S::ContinuousTimeMode,
            false,
        ) => Err(format!(
            "serialized state machine state {} has no simulator state",
            st.state.name()
        )),
        (S::Instantiated | S::InitializationMode, true) => Err(format!(
            "serialized state machine state {} cannot carry a simulator state",
            st.state.name()
        )),
        _ => Ok(()),
    }
}
