% A noisy task, written for planerel's tests: an object is good when it is red,
% but two of the 40 labels are wrong (o4 is red but negative, o2 is blue but positive).
% With noise 0 no general clause is consistent; noise/minacc let the learner accept
% the clause that makes a few errors.

:- set(i, 1).
:- set(clauselength, 3).

:- modeh(1, good(+obj)).
:- modeb(1, colour(+obj, #colour)).
:- modeb(1, size(+obj, #size)).
:- modeb(1, shape(+obj, #shape)).

:- determination(good/1, colour/2).
:- determination(good/1, size/2).
:- determination(good/1, shape/2).

obj(o1). colour(o1, red). size(o1, small). shape(o1, cube).
obj(o2). colour(o2, blue). size(o2, medium). shape(o2, cube).
obj(o3). colour(o3, green). size(o3, large). shape(o3, ball).
obj(o4). colour(o4, red). size(o4, small). shape(o4, ball).
obj(o5). colour(o5, blue). size(o5, large). shape(o5, cube).
obj(o6). colour(o6, green). size(o6, small). shape(o6, cube).
obj(o7). colour(o7, red). size(o7, medium). shape(o7, ball).
obj(o8). colour(o8, blue). size(o8, large). shape(o8, ball).
obj(o9). colour(o9, green). size(o9, small). shape(o9, cube).
obj(o10). colour(o10, red). size(o10, large). shape(o10, cube).
obj(o11). colour(o11, blue). size(o11, small). shape(o11, ball).
obj(o12). colour(o12, green). size(o12, medium). shape(o12, ball).
obj(o13). colour(o13, red). size(o13, large). shape(o13, cube).
obj(o14). colour(o14, blue). size(o14, small). shape(o14, cube).
obj(o15). colour(o15, green). size(o15, large). shape(o15, ball).
obj(o16). colour(o16, red). size(o16, small). shape(o16, ball).
obj(o17). colour(o17, blue). size(o17, medium). shape(o17, cube).
obj(o18). colour(o18, green). size(o18, large). shape(o18, cube).
obj(o19). colour(o19, red). size(o19, small). shape(o19, ball).
obj(o20). colour(o20, blue). size(o20, large). shape(o20, ball).
obj(o21). colour(o21, green). size(o21, small). shape(o21, cube).
obj(o22). colour(o22, red). size(o22, medium). shape(o22, cube).
obj(o23). colour(o23, blue). size(o23, large). shape(o23, ball).
obj(o24). colour(o24, green). size(o24, small). shape(o24, ball).
obj(o25). colour(o25, red). size(o25, large). shape(o25, cube).
obj(o26). colour(o26, blue). size(o26, small). shape(o26, cube).
obj(o27). colour(o27, green). size(o27, medium). shape(o27, ball).
obj(o28). colour(o28, red). size(o28, large). shape(o28, ball).
obj(o29). colour(o29, blue). size(o29, small). shape(o29, cube).
obj(o30). colour(o30, green). size(o30, large). shape(o30, cube).
obj(o31). colour(o31, red). size(o31, small). shape(o31, ball).
obj(o32). colour(o32, blue). size(o32, medium). shape(o32, ball).
obj(o33). colour(o33, green). size(o33, large). shape(o33, cube).
obj(o34). colour(o34, red). size(o34, small). shape(o34, cube).
obj(o35). colour(o35, blue). size(o35, large). shape(o35, ball).
obj(o36). colour(o36, green). size(o36, small). shape(o36, ball).
obj(o37). colour(o37, red). size(o37, medium). shape(o37, cube).
obj(o38). colour(o38, blue). size(o38, large). shape(o38, cube).
obj(o39). colour(o39, green). size(o39, small). shape(o39, ball).
obj(o40). colour(o40, red). size(o40, large). shape(o40, ball).
