within ;
package Versioned
  model Gain
    parameter Real k = 3;
    Real y = k * time;
  end Gain;
  annotation(version = "2.0");
end Versioned;
