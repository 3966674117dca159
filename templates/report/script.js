// Show or hide layers of the drawings (orientation glyphs, vision labels, target marks, grid).
document.querySelectorAll("input[data-toggle]").forEach(function (box) {
  box.addEventListener("change", function () {
    document.body.classList.toggle(box.dataset.toggle, !box.checked);
  });
});
