within ;
package Q "a one-file package with a short name"
  import Lib.two "a package constant, not a class";
  import half = Lib.Sub.half;
  model M
    Real x = two * time + half;
  end M;
end Q;
