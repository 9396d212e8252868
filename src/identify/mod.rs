//! Identification: least squares, stepwise selection and fitting of error functions to data.
