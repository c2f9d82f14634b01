//! Variable table, scenes and the generated model description (filled in by the description layer).
