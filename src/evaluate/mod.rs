//! Standard evaluations: ISO 230-2 positioning accuracy (later: ISO 230-4 circular tests).
