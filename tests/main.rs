mod fmu;
